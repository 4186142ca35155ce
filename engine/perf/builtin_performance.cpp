// Built-in performances for demos, tests and dataset generation when no
// captured performance is at hand. All are sampled at 30 fps and start from
// the neutral face (every weight 0 at t = 0), so a simulation can start at rest.
// The emotion takes live in themed_performance.cpp.
#include <algorithm>
#include <cmath>
#include <functional>
#include <iterator>
#include <random>

#include "core/checksum.h"
#include "core/error.h"
#include "perf/performance.h"
#include "perf/themed_performance.h"

namespace facesr {
namespace {

constexpr double kFps = 30;

// Rig shapes that play the role of an ARKit base name: the name itself or its
// left/right halves, in ARKit ("mouthSmileLeft") or ICT ("mouthSmile_L") style.
std::vector<size_t> shapes_for(const std::string& base, const std::vector<std::string>& names) {
  std::vector<size_t> out;
  for (size_t i = 0; i < names.size(); ++i)
    for (const char* suffix : {"", "_L", "_R", "Left", "Right"})
      if (names[i] == base + suffix) out.push_back(i);
  return out;
}

// 0 → 1 → 0, linear, peaking at the midpoint.
double triangle(double t, double duration) { return std::max(0.0, 1.0 - std::abs(2 * t / duration - 1)); }

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Fades a take in and out over `ramp` seconds so it starts and ends neutral.
double envelope(double t, double duration, double ramp) {
  return smoothstep(t / ramp) * smoothstep((duration - t) / ramp);
}

using Curve = std::function<double(double t)>;

// Samples one curve per set of rig shapes (given by index) at 30 fps over [0, duration].
Performance sample(const std::string& name, double duration, const std::vector<std::string>& rig_names,
                   const std::vector<std::pair<std::vector<size_t>, Curve>>& curves) {
  Performance p;
  p.name = name;
  p.fps = kFps;
  p.names = rig_names;
  const int frames = int(std::lround(duration * kFps)) + 1;
  p.weights.assign(size_t(frames) * rig_names.size(), 0.0f);
  for (const auto& [shapes, curve] : curves)
    for (size_t s : shapes)
      for (int f = 0; f < frames; ++f)
        p.weights[size_t(f) * rig_names.size() + s] = float(std::clamp(curve(f / kFps), 0.0, 1.0));
  return p;
}

// Same, with shapes named by ARKit base name (see shapes_for).
Performance sample(const std::string& name, double duration, const std::vector<std::string>& rig_names,
                   const std::vector<std::pair<std::string, Curve>>& curves) {
  std::vector<std::pair<std::vector<size_t>, Curve>> indexed;
  for (const auto& [base, curve] : curves) indexed.emplace_back(shapes_for(base, rig_names), curve);
  return sample(name, duration, rig_names, indexed);
}

// Through control values c[i] at t = i·step, cosine-eased between them
// (velocities continuous, zero at the controls).
Curve eased_controls(std::vector<double> c, double step) {
  return [c = std::move(c), step](double t) {
    const int i = std::min(int(t / step), int(c.size()) - 2);
    const double u = std::clamp(t / step - i, 0.0, 1.0);
    return c[i] + (0.5 - 0.5 * std::cos(M_PI * u)) * (c[i + 1] - c[i]);
  };
}

Performance smile(const std::vector<std::string>& names) {
  return sample("smile", 2.0, names, {{"mouthSmile", [](double t) { return triangle(t, 2.0); }}});
}

Performance jaw(const std::vector<std::string>& names) {
  return sample("jaw", 2.0, names, {{"jawOpen", [](double t) { return triangle(t, 2.0); }}});
}

// Speech-like: syllables on the jaw at ~3 Hz, rounding (funnel, pucker)
// alternating slower, an intermittent smile and brow raises.
Performance talk(const std::vector<std::string>& names) {
  constexpr double T = 4.0;
  auto env = [](double t) { return envelope(t, T, 0.4); };
  auto bump = [](double x) { return 0.5 - 0.5 * std::cos(x); };
  auto pos2 = [](double x) { return std::pow(std::max(0.0, std::sin(x)), 2); };
  const double w = 2 * M_PI;
  return sample(
      "talk", T, names,
      {{"jawOpen",
        [=](double t) { return env(t) * (0.15 + 0.55 * bump(w * 3.0 * t) * (0.7 + 0.3 * std::sin(w * 0.4 * t))); }},
       {"mouthFunnel", [=](double t) { return env(t) * 0.6 * pos2(w * 0.75 * t); }},
       {"mouthPucker", [=](double t) { return env(t) * 0.5 * pos2(w * 0.75 * t + M_PI); }},
       {"mouthSmile", [=](double t) { return env(t) * 0.45 * bump(w * 0.5 * t); }},
       {"browInnerUp", [=](double t) { return env(t) * 0.7 * pos2(w * 0.5 * t + 1.0); }}});
}

// Uniform in [0, 1) from the generator's raw bits, because
// std::uniform_real_distribution differs between standard libraries and the
// built-in takes must be the same everywhere.
double uniform01(std::mt19937_64& gen) { return double(gen() >> 11) * 0x1.0p-53; }

// Every shape follows its own random curve through control values every
// 0.5 s (cosine-eased, so velocities are continuous and vanish at controls).
// The generator is seeded by a fixed number and the shape's name, so a shape
// moves the same way on every rig and every run.
Performance random(const std::vector<std::string>& names) {
  constexpr double T = 4.0, step = 0.5;
  constexpr int controls = int(T / step) + 1;
  std::vector<std::pair<std::vector<size_t>, Curve>> curves;
  for (size_t s = 0; s < names.size(); ++s) {
    const std::string& n = names[s];
    std::mt19937_64 gen(0x5eed5eedull ^ fnv1a64(n.data(), n.size()));
    std::vector<double> c(controls, 0.0);  // c[0] = 0 starts neutral
    for (int i = 1; i < controls; ++i) c[i] = uniform01(gen);
    curves.emplace_back(std::vector<size_t>{s}, eased_controls(c, step));
  }
  return sample("random", T, names, curves);
}

// The ARKit base names that "sparse" and "subtle" draw poses from.
const char* const kSparseBases[] = {
    "browDown",    "browInnerUp", "browOuterUp", "cheekPuff",   "cheekSquint",  "eyeBlink",    "eyeLookDown",
    "eyeLookIn",   "eyeLookOut",  "eyeLookUp",   "eyeSquint",   "eyeWide",      "jawForward",  "jawLeft",
    "jawOpen",     "jawRight",    "mouthClose",  "mouthDimple", "mouthFrown",   "mouthFunnel", "mouthLeft",
    "mouthLowerDown", "mouthPress", "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper",
    "mouthShrugLower", "mouthShrugUpper", "mouthSmile", "mouthStretch", "mouthUpperUp", "noseSneer"};
constexpr size_t kNumSparseBases = sizeof(kSparseBases) / sizeof(kSparseBases[0]);

// Control k of a pose take: min_count + (0 … count_choices - 1) distinct
// bases from kSparseBases, each at lo + span · U[0, 1), both halves of a paired
// shape with their own ±20 % (so poses are slightly asymmetric), at most 1.
void draw_pose(std::mt19937_64& gen, const std::vector<std::string>& names, int min_count, int count_choices,
               double lo, double span, int k, std::vector<std::vector<double>>& c) {
  const int count = min_count + int(gen() % uint64_t(count_choices));
  std::vector<size_t> chosen;
  while (int(chosen.size()) < count) {
    const size_t b = size_t(gen() % kNumSparseBases);
    if (std::find(chosen.begin(), chosen.end(), b) == chosen.end()) chosen.push_back(b);
  }
  for (size_t b : chosen) {
    const double w = lo + span * uniform01(gen);
    // Halves by name, so that each gets the same draw whatever the rig's order.
    std::vector<size_t> halves = shapes_for(kSparseBases[b], names);
    std::sort(halves.begin(), halves.end(), [&](size_t x, size_t y) { return names[x] < names[y]; });
    for (size_t shape : halves) c[shape][k] = std::min(1.0, w * (0.8 + 0.4 * uniform01(gen)));
  }
}

// Every shape cosine-eased through its controls c[shape], `step` s apart.
Performance eased_take(const std::string& name, double T, double step, const std::vector<std::string>& names,
                       const std::vector<std::vector<double>>& c) {
  std::vector<std::pair<std::vector<size_t>, Curve>> curves;
  for (size_t s = 0; s < names.size(); ++s)
    curves.emplace_back(std::vector<size_t>{s}, eased_controls(c[s], step));
  return sample(name, T, names, curves);
}

// Poses of a few shapes at a time, closer to real expressions than "random"
// (where all 53 move at once): every 0.4 s a new pose activates 2 to 5 ARKit
// base shapes at 0.3 to 1 (draw_pose), every other shape at 0; cosine-eased
// between poses, neutral at t = 0. The generator is seeded by a fixed number
// and draws from a fixed list of base names, so the take is the same on every
// rig and every run. "sparse-K" (K = 2 to 99) is another take of the same
// kind, from another seed; K = 1 is "sparse" itself.
Performance sparse_take(const std::vector<std::string>& names, int take) {
  constexpr double T = 4.0, step = 0.4;
  constexpr int poses = int(T / step + 0.5) + 1;
  // Take 1 keeps the original seed, so "sparse" and its datasets stay as they were.
  std::mt19937_64 gen(take == 1 ? 0x5ba25eull : 0x5ba25eull ^ (uint64_t(take) * 0x9e3779b97f4a7c15ull));
  std::vector<std::vector<double>> c(names.size(), std::vector<double>(poses, 0.0));
  for (int k = 1; k < poses; ++k) draw_pose(gen, names, 2, 4, 0.3, 0.7, k, c);
  return eased_take(take == 1 ? "sparse" : "sparse-" + std::to_string(take), T, step, names, c);
}

Performance sparse(const std::vector<std::string>& names) { return sparse_take(names, 1); }

// Small expressions that relax to neutral: every 0.3 s the face alternates
// between a pose of 1 to 3 ARKit base shapes at 0.02 to 0.3 (draw_pose) and
// neutral, cosine-eased, over 6 s. Half of its frames are the slow tails near
// rest. Those are where a network trained on full expressions is weakest: its
// error there is tiny in centimetres but can exceed the LR-embedded surface's,
// and few training frames come that close to rest. Fixed seed and base list,
// so the same on every rig and every run.
Performance subtle(const std::vector<std::string>& names) {
  constexpr double T = 6.0, step = 0.3;
  constexpr int controls = int(T / step + 0.5) + 1;
  std::mt19937_64 gen(0x5b7e1eull);
  std::vector<std::vector<double>> c(names.size(), std::vector<double>(controls, 0.0));
  for (int k = 1; k < controls; k += 2) draw_pose(gen, names, 1, 3, 0.02, 0.28, k, c);  // even k stay neutral
  return eased_take("subtle", T, step, names, c);
}

// Every rig shape on its own at three small weights (0.005, 0.02, 0.08), one
// frame each, in the rig's order, after a neutral first frame: 1 + 3 × shapes
// frames. Near rest the face responds about linearly to the weights, so these
// frames sample that response shape by shape; it is what decides the error in
// the last frames of a take before rest (anger's and fear's tails are one or
// two lip shapes at weights below 0.01). Quasistatic simulators need no
// easing between frames.
Performance nudge(const std::vector<std::string>& names) {
  static constexpr double kWeights[] = {0.005, 0.02, 0.08};
  Performance p;
  p.name = "nudge";
  p.fps = kFps;
  p.names = names;
  const size_t frames = 1 + std::size(kWeights) * names.size();
  p.weights.assign(frames * names.size(), 0.0f);
  size_t f = 1;
  for (size_t s = 0; s < names.size(); ++s)
    for (double w : kWeights) p.weights[f++ * names.size() + s] = float(w);
  return p;
}

// The K of "sparse-K", or 0 when the name is not of that form.
int sparse_take_number(const std::string& name) {
  const std::string prefix = "sparse-";
  if (name.size() <= prefix.size() || name.size() > prefix.size() + 2 || name.compare(0, prefix.size(), prefix) != 0)
    return 0;
  int k = 0;
  for (size_t i = prefix.size(); i < name.size(); ++i) {
    if (name[i] < '0' || name[i] > '9') return 0;
    k = 10 * k + (name[i] - '0');
  }
  return k >= 2 ? k : 0;
}

const std::vector<std::pair<std::string, Performance (*)(const std::vector<std::string>&)>>& table() {
  static const std::vector<std::pair<std::string, Performance (*)(const std::vector<std::string>&)>> t = {
      {"smile", smile},
      {"jaw", jaw},
      {"talk", talk},
      {"random", random},
      {"sparse", sparse},
      {"subtle", subtle},
      {"nudge", nudge},
      {"amazement", amazement_performance},
      {"anger", anger_performance},
      {"fear", fear_performance},
      {"pain", pain_performance}};
  return t;
}

}  // namespace

std::vector<std::string> builtin_performance_names() {
  std::vector<std::string> out;
  for (const auto& e : table()) out.push_back(e.first);
  return out;
}

Performance builtin_performance(const std::string& name, const std::vector<std::string>& rig_names) {
  for (const auto& e : table())
    if (e.first == name) return e.second(rig_names);
  if (const int take = sparse_take_number(name)) return sparse_take(rig_names, take);
  std::string valid;
  for (const auto& n : builtin_performance_names()) valid += (valid.empty() ? "" : ", ") + n;
  throw Error("unknown built-in performance '" + name + "' (valid: " + valid + ", sparse-2 ... sparse-99)");
}

}  // namespace facesr
