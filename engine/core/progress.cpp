#include "core/progress.h"

#include <cstdio>

namespace facesr {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Progress::Progress(std::string task, long total, bool enabled, long first)
    : task_(std::move(task)), total_(total), first_(first), enabled_(enabled),
      start_(std::chrono::steady_clock::now()), last_(start_ - std::chrono::seconds(10)) {}

void Progress::update(long done, const std::string& detail) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (done < total_ && std::chrono::duration<double>(now - last_).count() < 0.5) return;
  last_ = now;
  const double elapsed = seconds_since(start_);
  const double frac = total_ > 0 ? double(done) / double(total_) : 1.0;
  const long run = done - first_;
  const double eta = run > 0 ? elapsed * double(total_ - done) / double(run) : 0.0;
  std::fprintf(stderr, "[%s] %ld/%ld (%.0f%%) elapsed %.1fs ETA %.1fs %s\n", task_.c_str(), done,
               total_, 100.0 * frac, elapsed, eta, detail.c_str());
}

void Progress::finish(const std::string& detail) {
  if (!enabled_) return;
  std::fprintf(stderr, "[%s] done %ld in %.1fs %s\n", task_.c_str(), total_, seconds_since(start_),
               detail.c_str());
}

void StageLog::begin(const std::string& stage) {
  stage_ = stage;
  start_ = std::chrono::steady_clock::now();
  if (enabled_) std::fprintf(stderr, "[rig] %s ...\n", stage.c_str());
}

double StageLog::end(const std::string& detail) {
  const double s = seconds_since(start_);
  if (enabled_) std::fprintf(stderr, "[rig] %s done in %.2fs %s\n", stage_.c_str(), s, detail.c_str());
  return s;
}

}  // namespace facesr
