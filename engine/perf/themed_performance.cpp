// Emotion performances built from FACS action units (AUs) rather than
// hand-drawn curves, so each take is a recognisable, documented prototype:
// Ekman & Friesen's EMFACS prototypes for surprise, anger and fear, and the
// Prkachin–Solomon pain expression. Each AU drives a few ARKit shapes (the
// table below); an emotion is a set of AUs with an intensity per expression
// episode, over an onset–apex–offset envelope, plus a speech layer (jaw
// syllables and lip visemes) for part of the take. docs/performances.md lists
// the numbers and sources.
//
// Everything is closed-form in time: no random numbers, so every run and
// every rig gets the same curves.
#include "perf/themed_performance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace facesr {
namespace {

constexpr double kFps = 30;
constexpr double kDuration = 4.5;  // 136 frames
// A wide but not maximal opening: these are expressive, conversational
// takes, not yawns, and the cap keeps expression and speech from summing
// into an extreme jaw.
constexpr double kMaxJawOpen = 0.6;

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// One expression episode: onset over [t0, t1], apex [t1, t2], offset over [t2, t3].
struct Pulse {
  double t0, t1, t2, t3;
  double at(double t) const { return smoothstep((t - t0) / (t1 - t0)) * smoothstep((t3 - t) / (t3 - t2)); }
};

// ARKit shapes an action unit moves, by base name (sides handled later), with
// the weight each gets at full AU intensity. Where ARKit has a direct
// counterpart the gain is 1; the jaw AUs are scaled so AU26 (jaw drop) at
// full intensity opens to 0.45 and AU27 (mouth stretch, a wide-open jaw) to 0.6.
struct AuShape {
  const char* base;
  double gain;
};

const std::map<int, std::vector<AuShape>>& au_shapes() {
  static const std::map<int, std::vector<AuShape>> table = {
      {1, {{"browInnerUp", 1.0}}},                                  // inner brow raiser
      {2, {{"browOuterUp", 1.0}}},                                  // outer brow raiser
      {4, {{"browDown", 1.0}}},                                     // brow lowerer
      {5, {{"eyeWide", 1.0}}},                                      // upper lid raiser
      {6, {{"cheekSquint", 1.0}}},                                  // cheek raiser
      {7, {{"eyeSquint", 1.0}}},                                    // lid tightener
      {9, {{"noseSneer", 1.0}, {"mouthUpperUp", 0.3}}},             // nose wrinkler (lifts the lip a little)
      {10, {{"mouthUpperUp", 1.0}}},                                // upper lip raiser
      {12, {{"mouthSmile", 1.0}}},                                  // lip corner puller
      {15, {{"mouthFrown", 1.0}}},                                  // lip corner depressor
      {17, {{"mouthShrugLower", 1.0}, {"mouthShrugUpper", 0.3}}},  // chin raiser
      {20, {{"mouthStretch", 1.0}}},                                // lip stretcher
      {23, {{"mouthPress", 0.3}, {"mouthRollLower", 0.25}, {"mouthRollUpper", 0.25}}},  // lip tightener
      {24, {{"mouthPress", 1.0}}},                                  // lip presser
      {25, {{"mouthLowerDown", 0.5}, {"mouthUpperUp", 0.1}}},       // lips part
      {26, {{"jawOpen", 0.45}, {"mouthLowerDown", 0.2}}},           // jaw drop
      {27, {{"jawOpen", 0.6}, {"mouthStretch", 0.2}}},              // mouth stretch (jaw wide open)
      {43, {{"eyeBlink", 1.0}}},                                    // eyes closed
  };
  return table;
}

// One AU of an emotion: its intensity in each episode (0..1; FACS A..E
// roughly 0.15, 0.3, 0.5, 0.7, 0.9), a delay relative to the episode
// envelope, and how much of it is released while speaking (lip AUs that the
// articulation overrides).
struct AuUse {
  int au;
  std::vector<double> intensity;  // one per Pulse
  double lag = 0;                 // s; negative leads
  double speech_release = 0;      // fraction removed at full speech
};

// Speech: syllables at `rate_hz` from `start`, each a consonant onset and a
// vowel ("ma", "-o" for none): the jaw opens mid-syllable by a vowel-dependent
// amount on top of a small base, lips shape the vowel, and bilabials close the
// lips at the syllable boundary where the jaw is at its lowest.
struct Speech {
  double start, rate_hz;
  std::vector<const char*> syllables;
  double end() const { return start + syllables.size() / rate_hz; }
};

struct Emotion {
  std::string name;
  std::vector<Pulse> pulses;
  std::vector<AuUse> aus;
  Speech speech;
  double asymmetry;  // left side × (1 + a), right × (1 − a)
  double right_lag;  // s; the right side moves a little later (faces are rarely synchronous)
};

// Face state of one frame: ARKit base name → (left, right) weight. Shapes
// with no side read the mean.
using Face = std::map<std::string, std::array<double, 2>>;

void add(Face& face, const std::string& base, double left, double right) {
  auto& v = face[base];
  v[0] += left;
  v[1] += right;
}

double jaw_for_vowel(char v) {
  switch (v) {
    case 'a': return 0.20;
    case 'o': return 0.15;
    case 'e': return 0.12;
    case 'i': return 0.08;
    case 'u': return 0.07;
    default: return 0.10;
  }
}

// How much speech is active at t (0..1), with short ramps so the jaw's base
// opening does not jump.
double speech_level(const Speech& s, double t) {
  return smoothstep((t - s.start) / 0.12) * smoothstep((s.end() - t) / 0.12);
}

// Adds the speech layer; returns the weight (0..1) of a bilabial closure at
// t, which closes the lips against whatever the jaw opening ends up being.
double add_speech(const Speech& s, double t, Face& face) {
  const double level = speech_level(s, t);
  if (level <= 0) return 0;
  const int n = int(s.syllables.size());
  const double phase = (t - s.start) * s.rate_hz;
  const int k = std::clamp(int(std::floor(phase)), 0, n - 1);
  const double u = phase - k;  // position in the syllable
  const double vowel = std::pow(std::sin(M_PI * u), 2);
  const char v = s.syllables[k][1];
  add(face, "jawOpen", level * (0.05 + jaw_for_vowel(v) * vowel), level * (0.05 + jaw_for_vowel(v) * vowel));
  auto both = [&](const char* base, double w) { add(face, base, level * w, level * w); };
  switch (v) {
    case 'o': both("mouthFunnel", 0.35 * vowel); break;
    case 'u': both("mouthPucker", 0.45 * vowel), both("mouthFunnel", 0.15 * vowel); break;
    case 'e': both("mouthStretch", 0.15 * vowel); break;
    case 'i': both("mouthSmile", 0.12 * vowel), both("mouthStretch", 0.1 * vowel); break;
    case 'a': both("mouthLowerDown", 0.12 * vowel); break;
    default: break;
  }
  // The consonant of the nearest syllable boundary, as a narrow burst there.
  const int b = int(std::lround(phase));
  if (b < 0 || b >= n) return 0;
  const double burst = std::pow(std::cos(M_PI * (phase - b)), 4);
  switch (s.syllables[b][0]) {
    case 'm': case 'b': case 'p': both("mouthPress", 0.1 * burst); return level * burst;
    case 'f': case 'v': both("mouthRollLower", 0.35 * burst); break;
    case 'w': both("mouthPucker", 0.5 * burst); break;
    default: break;
  }
  return 0;
}

Face face_at(const Emotion& e, double t) {
  Face face;
  const double speaking = speech_level(e.speech, t);
  for (const AuUse& use : e.aus) {
    double side[2];
    for (int s = 0; s < 2; ++s) {
      const double ts = t - use.lag - (s == 1 ? e.right_lag : 0.0);
      double v = 0;
      for (size_t p = 0; p < e.pulses.size(); ++p) v += use.intensity[p] * e.pulses[p].at(ts);
      side[s] = v * (1 - use.speech_release * speaking) * (s == 0 ? 1 + e.asymmetry : 1 - e.asymmetry);
    }
    for (const AuShape& shape : au_shapes().at(use.au))
      add(face, shape.base, shape.gain * side[0], shape.gain * side[1]);
  }
  const double bilabial = add_speech(e.speech, t, face);
  auto& jaw = face["jawOpen"];
  for (double& j : jaw) j = std::min(j, kMaxJawOpen);
  // Lips meet over the open jaw: mouthClose equal to jawOpen closes them.
  if (bilabial > 0) add(face, "mouthClose", bilabial * jaw[0], bilabial * jaw[1]);
  return face;
}

// Rig shapes for an ARKit base name, with the side they take (0 left, 1
// right, 2 the mean of both): ARKit ("browDownLeft") or ICT ("browDown_L") style.
std::vector<std::pair<size_t, int>> rig_shapes(const std::string& base, const std::vector<std::string>& names) {
  std::vector<std::pair<size_t, int>> out;
  for (size_t i = 0; i < names.size(); ++i) {
    if (names[i] == base) out.emplace_back(i, 2);
    if (names[i] == base + "_L" || names[i] == base + "Left") out.emplace_back(i, 0);
    if (names[i] == base + "_R" || names[i] == base + "Right") out.emplace_back(i, 1);
  }
  return out;
}

Performance render(const Emotion& e, const std::vector<std::string>& names) {
  Performance p;
  p.name = e.name;
  p.fps = kFps;
  p.names = names;
  const int frames = int(std::lround(kDuration * kFps)) + 1;
  p.weights.assign(size_t(frames) * names.size(), 0.0f);
  std::map<std::string, std::vector<std::pair<size_t, int>>> slots;
  for (int f = 0; f < frames; ++f) {
    const double t = f / kFps;
    // Exactly neutral at both ends whatever the episodes do.
    const double fade = smoothstep(t / 0.15) * smoothstep((kDuration - t) / 0.15);
    for (const auto& [base, lr] : face_at(e, t)) {
      auto it = slots.find(base);
      if (it == slots.end()) it = slots.emplace(base, rig_shapes(base, names)).first;
      for (const auto& [index, side] : it->second) {
        const double v = side == 2 ? 0.5 * (lr[0] + lr[1]) : lr[side];
        p.weights[size_t(f) * names.size() + index] = float(std::clamp(fade * v, 0.0, 1.0) + 0.0);
      }
    }
  }
  return p;
}

}  // namespace

// Surprise turned amazement: brows shoot up and the eyes widen within a
// quarter second, the jaw drops; a second, weaker wave comes with "wow, look
// at that".
Performance amazement_performance(const std::vector<std::string>& names) {
  const Emotion e{"amazement",
                  {{0.30, 0.55, 1.50, 2.10}, {2.45, 2.85, 3.55, 4.25}},
                  {{1, {0.85, 0.60}},
                   {2, {0.80, 0.55}, 0.03},
                   {5, {0.70, 0.35}, -0.03},
                   {26, {0.80, 0.35}, 0.05},
                   {25, {0.60, 0.40}, 0.05, 0.5}},
                  {2.10, 4.0, {"wo", "wa", "lu", "ka", "-a", "ta"}},
                  0.07,
                  1 / kFps};
  return render(e, names);
}

// Anger: a frown and glare with pressed lips, a burst of speech ("what did
// you do") that frees the lips, then a stronger second wave with the lips
// pressed again.
Performance anger_performance(const std::vector<std::string>& names) {
  const Emotion e{"anger",
                  {{0.25, 0.70, 1.60, 2.30}, {1.70, 2.50, 3.60, 4.25}},
                  {{4, {0.70, 0.90}},
                   {5, {0.45, 0.55}, -0.05},
                   {7, {0.55, 0.70}, 0.05},
                   {23, {0.50, 0.55}, 0.0, 0.8},
                   {24, {0.50, 0.60}, 0.0, 0.85},
                   {17, {0.35, 0.45}, 0.0, 0.8},
                   {10, {0.10, 0.30}, 0.1}},
                  {1.85, 4.5, {"wa", "ta", "di", "ju", "du"}},
                  -0.08,
                  2 / kFps};
  return render(e, names);
}

// Fear: raised and drawn-together brows, wide eyes, lips stretched back, the
// jaw dropped; a quick trembling "no, no, please" between two episodes.
Performance fear_performance(const std::vector<std::string>& names) {
  const Emotion e{"fear",
                  {{0.35, 0.70, 1.70, 2.30}, {2.30, 2.80, 3.50, 4.20}},
                  {{1, {0.80, 0.60}},
                   {2, {0.50, 0.40}},
                   {4, {0.50, 0.40}},
                   {5, {0.80, 0.55}, -0.05},
                   {7, {0.30, 0.25}},
                   {20, {0.70, 0.50}, 0.08, 0.5},
                   {26, {0.50, 0.30}, 0.05},
                   {25, {0.50, 0.40}, 0.05, 0.5}},
                  {1.90, 5.0, {"no", "no", "pi", "wi", "-o", "mo", "-u"}},
                  0.06,
                  1 / kFps};
  return render(e, names);
}

// Pain: a sudden grimace (lowered brows, squeezed eyes and cheeks, wrinkled
// nose, raised upper lip) with a slow release, a moan ("ow... ah... oh my"),
// and a second, weaker wave.
Performance pain_performance(const std::vector<std::string>& names) {
  const Emotion e{"pain",
                  {{0.20, 0.40, 1.10, 1.80}, {2.30, 2.70, 3.30, 4.20}},
                  {{4, {0.75, 0.55}},
                   {6, {0.70, 0.50}},
                   {7, {0.75, 0.55}},
                   {9, {0.60, 0.40}},
                   {10, {0.45, 0.30}, 0.05},
                   {43, {0.70, 0.30}, 0.05},
                   {20, {0.35, 0.25}, 0.05, 0.5},
                   {25, {0.50, 0.30}, 0.0, 0.5},
                   {26, {0.30, 0.20}, 0.05}},
                  {1.75, 3.0, {"-a", "-o", "wa", "ma", "-o"}},
                  -0.08,
                  1 / kFps};
  return render(e, names);
}

}  // namespace facesr
