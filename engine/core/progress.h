#pragma once
#include <chrono>
#include <string>

namespace facesr {

// Progress of long work, on stderr (stdout is reserved for --json output).
// Prints at most a few lines per second with percentage and ETA.
class Progress {
 public:
  // first: work already done before this run (a resumed job), so that the
  // ETA comes from this run's rate.
  Progress(std::string task, long total, bool enabled = true, long first = 0);
  void update(long done, const std::string& detail = "");
  // `count` units found already done mid-run (a finished part of a resumed
  // job): they count toward `done` but not toward the rate behind the ETA.
  void skip(long count) { first_ += count; }
  void finish(const std::string& detail = "");

 private:
  std::string task_;
  long total_, first_;
  bool enabled_;
  std::chrono::steady_clock::time_point start_, last_;
};

// Stage timer for multi-step jobs: "[rig] tetrahedralize ... 3.2 s".
class StageLog {
 public:
  explicit StageLog(bool enabled) : enabled_(enabled) {}
  void begin(const std::string& stage);
  double end(const std::string& detail = "");  // returns seconds
  bool enabled() const { return enabled_; }

 private:
  bool enabled_;
  std::string stage_;
  std::chrono::steady_clock::time_point start_;
};

double seconds_since(std::chrono::steady_clock::time_point t0);

}  // namespace facesr
