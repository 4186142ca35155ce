#pragma once
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "perf/performance.h"
#include "rig/rig.h"
#include "sim/simulator.h"

namespace facesr {

// `count` control frames that a performance would never ask for, in rig
// order, from `seed`: every shape alone at 1 straight from rest, all shapes
// at 1, jumps between rest and full random poses, opposing shapes together
// (jawLeft + jawRight + jawOpen + jawForward, smile + frown, ...), and random
// poses of a few to all shapes at weights up to 1. Consecutive frames are
// far apart on purpose: no warm start helps.
Performance robustness_extreme_frames(const std::vector<std::string>& names, int count, uint32_t seed);

struct RobustnessRow {
  std::string performance;
  int frames = 0, unconverged = 0, recovered = 0, diverged = 0, nan_frames = 0;
  int inverted_max = 0;
  double max_rel_residual = 0;  // over frames that were not diverged
  double mean_step_ms = 0, p95_step_ms = 0;  // wall time per frame, recovery included
  // The first diverged frames, so that a failure can be replayed: frame
  // index, last attempt's relative residual and inverted tets.
  struct Failure {
    int frame = 0;
    double rel_residual = 0;
    int inverted_tets = 0;
  };
  std::vector<Failure> failures;  // at most kMaxFailures per row
  static constexpr size_t kMaxFailures = 10;
  nlohmann::json to_json() const;
  nlohmann::json failures_json() const;
};

// Runs each performance (from rest, frames in order) through `sim` and
// counts what became of its frames; a frame whose returned positions are
// not finite counts as NaN (the recovering simulator should make that
// impossible). `max_frames` > 0 caps the frames per performance.
// `progress` (may be empty) is called after every frame.
std::vector<RobustnessRow> run_robustness(Simulator& sim, const Rig& rig, const std::vector<Performance>& perfs,
                                          int max_frames, const std::function<void(const std::string&)>& progress);

// Totals over rows (performance "all").
RobustnessRow robustness_total(const std::vector<RobustnessRow>& rows);

}  // namespace facesr
