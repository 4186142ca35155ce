// The FACS-based emotion performances: shape, range, neutral ends,
// determinism, each emotion's key action units at its apex, speech-like jaw
// motion, and left/right asymmetry.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "perf/performance.h"
#include "test_support.h"

using namespace facesr;

namespace {

// The ICT FaceKit's 53 ARKit-style expressions (its vertex_indices.json order).
const std::vector<std::string> kIct = {
    "browDown_L",       "browDown_R",       "browInnerUp_L",   "browInnerUp_R",   "browOuterUp_L",  "browOuterUp_R",
    "cheekPuff_L",      "cheekPuff_R",      "cheekSquint_L",   "cheekSquint_R",   "eyeBlink_L",     "eyeBlink_R",
    "eyeLookDown_L",    "eyeLookDown_R",    "eyeLookIn_L",     "eyeLookIn_R",     "eyeLookOut_L",   "eyeLookOut_R",
    "eyeLookUp_L",      "eyeLookUp_R",      "eyeSquint_L",     "eyeSquint_R",     "eyeWide_L",      "eyeWide_R",
    "jawForward",       "jawLeft",          "jawOpen",         "jawRight",        "mouthClose",     "mouthDimple_L",
    "mouthDimple_R",    "mouthFrown_L",     "mouthFrown_R",    "mouthFunnel",     "mouthLeft",      "mouthLowerDown_L",
    "mouthLowerDown_R", "mouthPress_L",     "mouthPress_R",    "mouthPucker",     "mouthRight",     "mouthRollLower",
    "mouthRollUpper",   "mouthShrugLower",  "mouthShrugUpper", "mouthSmile_L",    "mouthSmile_R",   "mouthStretch_L",
    "mouthStretch_R",   "mouthUpperUp_L",   "mouthUpperUp_R",  "noseSneer_L",     "noseSneer_R"};

const std::vector<std::string> kThemes = {"amazement", "anger", "fear", "pain"};

int index_of(const Performance& p, const std::string& name) {
  const auto it = std::find(p.names.begin(), p.names.end(), name);
  EXPECT_NE(it, p.names.end()) << name;
  return int(it - p.names.begin());
}

float peak(const Performance& p, const std::string& name) { return max_weights(p)[index_of(p, name)]; }

// Strict rises followed by a non-rise: syllable peaks of the jaw.
int local_maxima(const Performance& p, const std::string& name, float floor) {
  const int s = index_of(p, name);
  int n = 0;
  for (int f = 1; f + 1 < p.frames(); ++f) {
    const float a = p.frame(f - 1)[s], b = p.frame(f)[s], c = p.frame(f + 1)[s];
    if (b > a && b >= c && b > floor) ++n;
  }
  return n;
}

}  // namespace

TEST(ThemedPerformance, ListedWellFormedNeutralAtBothEndsAndDeterministic) {
  const std::vector<std::string> all = builtin_performance_names();
  for (const std::string& name : kThemes) {
    ASSERT_NE(std::find(all.begin(), all.end(), name), all.end()) << name;
    const Performance p = builtin_performance(name, kIct);
    EXPECT_EQ(p.name, name);
    EXPECT_EQ(p.fps, 30);
    EXPECT_EQ(p.start_time, 0);
    EXPECT_FALSE(p.has_jaw);
    ASSERT_EQ(p.frames(), 136) << name;
    EXPECT_DOUBLE_EQ(p.duration(), 4.5);
    for (size_t s = 0; s < kIct.size(); ++s) {
      EXPECT_EQ(p.frame(0)[s], 0.0f) << name << " " << kIct[s];
      EXPECT_EQ(p.frame(135)[s], 0.0f) << name << " " << kIct[s];
    }
    for (float v : p.weights) ASSERT_TRUE(v >= 0 && v <= 1) << name << ": weight " << v;
    EXPECT_LE(peak(p, "jawOpen"), 0.6f) << name;
    EXPECT_TRUE(builtin_performance(name, kIct).weights == p.weights) << name << " is not deterministic";
  }
}

TEST(ThemedPerformance, KeyActionUnitsAtApex) {
  // Each emotion's defining shapes reach above 0.3 (both sides where sided).
  const std::map<std::string, std::vector<std::string>> keys = {
      {"amazement", {"browInnerUp_L", "browInnerUp_R", "browOuterUp_L", "browOuterUp_R", "eyeWide_L", "jawOpen"}},
      {"anger", {"browDown_L", "browDown_R", "eyeSquint_L", "eyeSquint_R", "mouthPress_L", "mouthPress_R",
                 "mouthShrugLower"}},
      {"fear", {"browInnerUp_L", "browInnerUp_R", "eyeWide_L", "eyeWide_R", "mouthStretch_L", "mouthStretch_R"}},
      {"pain", {"browDown_L", "browDown_R", "eyeSquint_L", "cheekSquint_R", "noseSneer_L", "noseSneer_R",
                "mouthUpperUp_L", "eyeBlink_L"}}};
  for (const auto& [name, shapes] : keys) {
    const Performance p = builtin_performance(name, kIct);
    for (const std::string& s : shapes) EXPECT_GT(peak(p, s), 0.3f) << name << ": " << s;
  }
  // And the prototypes stay apart: no lowered brows in amazement, no raised
  // outer brows in anger or pain, no smile anywhere but a speech viseme's trace.
  EXPECT_EQ(peak(builtin_performance("amazement", kIct), "browDown_L"), 0.0f);
  EXPECT_EQ(peak(builtin_performance("anger", kIct), "browOuterUp_L"), 0.0f);
  EXPECT_EQ(peak(builtin_performance("pain", kIct), "browOuterUp_R"), 0.0f);
  EXPECT_EQ(peak(builtin_performance("pain", kIct), "eyeWide_R"), 0.0f);
  for (const std::string& name : kThemes) EXPECT_LT(peak(builtin_performance(name, kIct), "mouthSmile_L"), 0.15f);
}

TEST(ThemedPerformance, SpeechLikeJawAndVisemes) {
  for (const std::string& name : kThemes) {
    const Performance p = builtin_performance(name, kIct);
    EXPECT_GE(local_maxima(p, "jawOpen", 0.05f), 3) << name;
    // Syllables: the jaw swings by more than 0.05 between neighbouring peaks and troughs.
    const int s = index_of(p, "jawOpen");
    float swing = 0;
    for (int f = 3; f < p.frames(); ++f)
      swing = std::max(swing, std::abs(p.frame(f)[s] - p.frame(f - 3)[s]));
    EXPECT_GT(swing, 0.05f) << name;
    // Some lip viseme moves.
    const float lips = std::max({peak(p, "mouthClose"), peak(p, "mouthFunnel"), peak(p, "mouthPucker")});
    EXPECT_GT(lips, 0.1f) << name;
  }
}

TEST(ThemedPerformance, SmallLeftRightAsymmetry) {
  for (const std::string& name : kThemes) {
    const Performance p = builtin_performance(name, kIct);
    float largest = 0, differs = 0;
    for (const std::string base : {"browDown", "browInnerUp", "eyeSquint", "eyeWide", "mouthStretch"}) {
      const int l = index_of(p, base + "_L"), r = index_of(p, base + "_R");
      for (int f = 0; f < p.frames(); ++f) {
        largest = std::max({largest, p.frame(f)[l], p.frame(f)[r]});
        differs = std::max(differs, std::abs(p.frame(f)[l] - p.frame(f)[r]));
      }
    }
    EXPECT_GT(differs, 0.02f) << name << ": left and right move identically";
    EXPECT_LT(differs, 0.35f * largest) << name << ": asymmetry is not small";
  }
}

TEST(ThemedPerformance, OtherRigNamingsAndMissingShapes) {
  // The procedural head lacks most eye and lip shapes; they are skipped.
  const std::vector<std::string>& names = fixtures::procedural_rig().blendshape_names;
  for (const std::string& name : kThemes) {
    const Performance p = builtin_performance(name, names);
    ASSERT_EQ(p.frames(), 136);
    EXPECT_EQ(p.names, names);
    EXPECT_GT(peak(p, "jawOpen"), 0.1f) << name;
    for (float v : p.weights) ASSERT_TRUE(v >= 0 && v <= 1);
  }
  EXPECT_GT(peak(builtin_performance("anger", names), "browDown_R"), 0.3f);
  // ARKit naming: Left/Right suffixes.
  const Performance a = builtin_performance("fear", {"browInnerUpLeft", "browInnerUpRight", "mouthStretchLeft"});
  EXPECT_GT(a.frame(30)[0], 0.3f);
  EXPECT_GT(a.frame(30)[1], 0.3f);
  EXPECT_NE(a.frame(30)[0], a.frame(30)[1]);
}
