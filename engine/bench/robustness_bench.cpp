#include "bench/robustness_bench.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>

#include "core/error.h"
#include "core/progress.h"
#include "perf/perf_controls.h"

namespace facesr {

namespace {

int shape_index(const std::vector<std::string>& names, const std::string& n) {
  const auto it = std::find(names.begin(), names.end(), n);
  return it == names.end() ? -1 : int(it - names.begin());
}

double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(std::ceil(q * double(v.size())) - 1))];
}

}  // namespace

Performance robustness_extreme_frames(const std::vector<std::string>& names, int count, uint32_t seed) {
  require(count > 0, "robustness_extreme_frames: count must be positive");
  const size_t S = names.size();
  Performance p;
  p.name = "extremes";
  p.fps = 30;
  p.names = names;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  std::vector<std::vector<float>> frames;
  const std::vector<float> rest(S, 0.0f);
  for (size_t s = 0; s < S; ++s) {  // each shape alone at full weight, from rest
    std::vector<float> w(S, 0.0f);
    w[s] = 1;
    frames.push_back(w);
    frames.push_back(rest);
  }
  frames.emplace_back(S, 1.0f);
  frames.push_back(rest);
  // Opposing shapes together.
  const std::vector<std::vector<std::string>> opposed = {
      {"jawOpen", "jawLeft", "jawRight", "jawForward"}, {"jawLeft", "jawRight"}, {"jawOpen", "mouthClose"},
      {"mouthSmile_L", "mouthSmile_R", "mouthFrown_L", "mouthFrown_R"}, {"mouthPucker", "mouthStretch_L", "mouthStretch_R"},
      {"mouthLeft", "mouthRight"}, {"eyeBlink_L", "eyeWide_L", "eyeBlink_R", "eyeWide_R"},
      {"browDown_L", "browOuterUp_L", "browDown_R", "browOuterUp_R"}, {"mouthRollUpper", "mouthRollLower", "jawOpen"},
      {"mouthFunnel", "mouthPress_L", "mouthPress_R", "jawForward"}};
  for (const auto& group : opposed) {
    std::vector<float> w(S, 0.0f);
    int found = 0;
    for (const auto& n : group)
      if (const int i = shape_index(names, n); i >= 0) w[size_t(i)] = 1, ++found;
    if (found > 1) frames.push_back(w);
  }
  // Random poses: jumps from rest, then runs of unrelated poses.
  while (int(frames.size()) < count) {
    std::vector<float> w(S, 0.0f);
    const float density = u(rng);  // from a few shapes to all of them
    for (size_t s = 0; s < S; ++s)
      if (u(rng) < density) w[s] = u(rng) < 0.3f ? 1.0f : u(rng);
    frames.push_back(w);
    if (u(rng) < 0.25f && int(frames.size()) < count) frames.push_back(rest);
  }
  frames.resize(size_t(count));
  for (const auto& w : frames) p.weights.insert(p.weights.end(), w.begin(), w.end());
  return p;
}

nlohmann::json RobustnessRow::to_json() const {
  return {{"performance", performance},   {"frames", frames},
          {"unconverged_frames", unconverged}, {"recovered_frames", recovered},
          {"diverged_frames", diverged},  {"nan_frames", nan_frames},
          {"inverted_tets_max", inverted_max}, {"max_rel_residual", max_rel_residual},
          {"mean_step_ms", mean_step_ms}, {"p95_step_ms", p95_step_ms}, {"failures", failures_json()}};
}

nlohmann::json RobustnessRow::failures_json() const {
  nlohmann::json a = nlohmann::json::array();
  for (const Failure& f : failures)
    a.push_back({{"frame", f.frame}, {"rel_residual", f.rel_residual}, {"inverted_tets", f.inverted_tets}});
  return a;
}

std::vector<RobustnessRow> run_robustness(Simulator& sim, const Rig& rig, const std::vector<Performance>& perfs,
                                          int max_frames, const std::function<void(const std::string&)>& progress) {
  std::vector<RobustnessRow> rows;
  std::vector<double> x;
  for (const Performance& p : perfs) {
    RobustnessRow r;
    r.performance = p.name;
    sim.reset();
    Controls c;
    const int F = max_frames > 0 ? std::min(max_frames, p.frames()) : p.frames();
    std::vector<double> ms;
    for (int f = 0; f < F; ++f) {
      frame_controls(p, f, rig.jaw, c);
      const auto t0 = std::chrono::steady_clock::now();
      const StepStats st = sim.step(c);
      ms.push_back(1e3 * seconds_since(t0));
      sim.nodes(x);
      bool finite = true;
      for (double v : x) finite = finite && std::isfinite(v);
      r.nan_frames += !finite;
      r.unconverged += st.status == StepStatus::Unconverged;
      r.recovered += st.status == StepStatus::Recovered;
      r.diverged += st.status == StepStatus::Diverged;
      if (st.status == StepStatus::Diverged && r.failures.size() < RobustnessRow::kMaxFailures)
        r.failures.push_back({f, st.rel_residual, st.inverted_tets});
      if (st.status != StepStatus::Diverged) {
        r.inverted_max = std::max(r.inverted_max, st.inverted_tets);
        r.max_rel_residual = std::max(r.max_rel_residual, st.rel_residual);
      }
      if (progress) progress(p.name);
    }
    r.frames = F;
    for (double v : ms) r.mean_step_ms += v / std::max(1, F);
    r.p95_step_ms = pct(ms, 0.95);
    rows.push_back(r);
  }
  return rows;
}

RobustnessRow robustness_total(const std::vector<RobustnessRow>& rows) {
  RobustnessRow t;
  t.performance = "all";
  double time = 0;
  for (const auto& r : rows) {
    t.frames += r.frames;
    t.unconverged += r.unconverged;
    t.recovered += r.recovered;
    t.diverged += r.diverged;
    t.nan_frames += r.nan_frames;
    t.inverted_max = std::max(t.inverted_max, r.inverted_max);
    t.max_rel_residual = std::max(t.max_rel_residual, r.max_rel_residual);
    t.p95_step_ms = std::max(t.p95_step_ms, r.p95_step_ms);
    time += r.mean_step_ms * r.frames;
  }
  t.mean_step_ms = t.frames > 0 ? time / t.frames : 0;
  return t;
}

}  // namespace facesr
