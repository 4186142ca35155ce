// Performances: keyframe sampling, every validation error, JSON round trip
// and the built-in performances.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "perf/performance.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;
using nlohmann::json;

namespace {

// The procedural head's blendshapes (engine/rig/procedural_head.cpp).
std::vector<std::string> procedural_names() {
  std::vector<std::string> n = {"jawOpen", "jawLeft", "jawRight", "jawForward"};
  for (const char* side : {"_L", "_R"})
    for (const char* base : {"mouthSmile", "mouthFrown", "browInnerUp", "browDown", "browOuterUp", "cheekPuff",
                             "mouthUpperUp", "mouthLowerDown", "noseSneer"})
      n.push_back(std::string(base) + side);
  n.push_back("mouthPucker");
  n.push_back("mouthFunnel");
  return n;
}

const std::vector<std::string> kNames = {"jawOpen", "mouthSmile_L", "mouthSmile_R"};

int index_of(const Performance& p, const std::string& name) {
  return int(std::find(p.names.begin(), p.names.end(), name) - p.names.begin());
}

float w(const Performance& p, int frame, const std::string& name) { return p.frame(frame)[index_of(p, name)]; }

json doc(double fps, json keyframes) {
  return {{"format", "facesr-performance"}, {"version", 1}, {"name", "t"}, {"fps", fps}, {"keyframes", keyframes}};
}

using fixtures::error_of;

class PerformanceFiles : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_perf_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p) << text;
    return p.string();
  }
  // Loads `j` from a file and returns the error message, which must name the file.
  static std::string file_error(const json& j) {
    const std::string path = write("bad.json", j.dump());
    const std::string msg = error_of([&] { load_performance_json(path, kNames); });
    EXPECT_NE(msg.find(path), std::string::npos) << msg;
    return msg;
  }
  static fs::path dir_;
};
fs::path PerformanceFiles::dir_;

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

}  // namespace

TEST(Performance, InterpolatesLinearlyBetweenKeyframes) {
  const json j = doc(4, {{{"time", 0.0}, {"weights", {{"jawOpen", 0.0}}}},
                         {{"time", 1.0}, {"weights", {{"jawOpen", 1.0}, {"mouthSmile_L", 0.5}}}},
                         {{"time", 2.0}, {"weights", {{"jawOpen", 0.0}}}}});
  const Performance p = performance_from_json(j, kNames, "test");
  EXPECT_EQ(p.name, "t");
  EXPECT_EQ(p.names, kNames);
  ASSERT_EQ(p.frames(), 9);  // t = 0, 0.25, ..., 2 inclusive
  EXPECT_DOUBLE_EQ(p.duration(), 2.0);
  // Exact keyframe times.
  EXPECT_EQ(w(p, 0, "jawOpen"), 0.0f);
  EXPECT_EQ(w(p, 4, "jawOpen"), 1.0f);
  EXPECT_EQ(w(p, 4, "mouthSmile_L"), 0.5f);
  EXPECT_EQ(w(p, 8, "jawOpen"), 0.0f);
  // In between.
  EXPECT_FLOAT_EQ(w(p, 1, "jawOpen"), 0.25f);
  EXPECT_FLOAT_EQ(w(p, 2, "jawOpen"), 0.5f);
  EXPECT_FLOAT_EQ(w(p, 2, "mouthSmile_L"), 0.25f);
  EXPECT_FLOAT_EQ(w(p, 7, "jawOpen"), 0.25f);
  // mouthSmile_L is unlisted in the last keyframe, so it falls back to 0 there.
  EXPECT_FLOAT_EQ(w(p, 6, "mouthSmile_L"), 0.25f);
  EXPECT_EQ(w(p, 8, "mouthSmile_L"), 0.0f);
  // A shape never listed stays exactly 0.
  for (int f = 0; f < p.frames(); ++f) EXPECT_EQ(w(p, f, "mouthSmile_R"), 0.0f);
}

TEST(Performance, FramesStartAtFirstKeyframeAndStopAtLast) {
  // Keyframes at 0.5 s and 1.55 s at 10 fps: frames at 0.5, 0.6, ..., 1.5; 1.55 is off the grid.
  const json j =
      doc(10, {{{"time", 0.5}, {"weights", {{"jawOpen", 0.0}}}}, {{"time", 1.55}, {"weights", {{"jawOpen", 1.0}}}}});
  const Performance p = performance_from_json(j, kNames, "test");
  ASSERT_EQ(p.frames(), 11);
  EXPECT_DOUBLE_EQ(p.start_time, 0.5);
  EXPECT_NEAR(p.time(10), 1.5, 1e-12);
  EXPECT_NEAR(w(p, 10, "jawOpen"), 1.0 / 1.05, 1e-6);
  // One keyframe: one frame.
  const Performance one =
      performance_from_json(doc(30, {{{"time", 2.0}, {"weights", {{"jawOpen", 0.7}}}}}), kNames, "test");
  ASSERT_EQ(one.frames(), 1);
  EXPECT_FLOAT_EQ(w(one, 0, "jawOpen"), 0.7f);
}

TEST_F(PerformanceFiles, MissingAndMalformedFiles) {
  const std::string missing = (dir_ / "nope.json").string();
  std::string msg = error_of([&] { load_performance_json(missing, kNames); });
  EXPECT_HAS(msg, missing);
  EXPECT_HAS(msg, "cannot open");
  const std::string bad = write("broken.json", "{\"format\": \"facesr-performance\", ");
  msg = error_of([&] { load_performance_json(bad, kNames); });
  EXPECT_HAS(msg, bad);
  EXPECT_HAS(msg, "not valid JSON");
  const std::string huge = write("huge.json", "{\"a\": 1e999}");
  msg = error_of([&] { load_performance_json(huge, kNames); });
  EXPECT_HAS(msg, huge);
  EXPECT_HAS(msg, "not valid JSON");
}

TEST_F(PerformanceFiles, HeaderErrors) {
  const json key = {{{"time", 0.0}, {"weights", {{"jawOpen", 0.0}}}}};
  json j = doc(30, key);
  j["format"] = "something-else";
  EXPECT_HAS(file_error(j), "'format'");
  j.erase("format");
  EXPECT_HAS(file_error(j), "'format' is missing");
  j = doc(30, key);
  j["version"] = 2;
  EXPECT_HAS(file_error(j), "unsupported version 2");
  j.erase("version");
  EXPECT_HAS(file_error(j), "'version' is missing");
  for (double fps : {0.0, -5.0, 1000.5}) EXPECT_HAS(file_error(doc(fps, key)), "not in (0, 1000]");
  j = doc(30, key);
  j["fps"] = "30";
  EXPECT_HAS(file_error(j), "'fps' is not a number");
  j.erase("fps");
  EXPECT_HAS(file_error(j), "'fps' is missing");
  j = doc(30, key);
  j["name"] = 7;
  EXPECT_HAS(file_error(j), "'name' is not a string");
  j = doc(30, key);
  j.erase("keyframes");
  EXPECT_HAS(file_error(j), "'keyframes' is missing");
  EXPECT_HAS(file_error(doc(30, json::array())), "at least 1 keyframe");
  EXPECT_HAS(file_error(json::array()), "not a JSON object");
  EXPECT_EQ(performance_from_json(doc(1000, key), kNames, "x").fps, 1000);  // the bound itself is allowed
}

TEST_F(PerformanceFiles, KeyframeTimeErrors) {
  auto k = [](double t) { return json{{"time", t}, {"weights", json::object()}}; };
  std::string msg = file_error(doc(30, {k(0), k(1), k(0.5)}));
  EXPECT_HAS(msg, "keyframe 2");
  EXPECT_HAS(msg, "strictly increasing");
  msg = file_error(doc(30, {k(0), k(1), k(1)}));
  EXPECT_HAS(msg, "keyframe 2");
  EXPECT_HAS(msg, "strictly increasing");
  msg = file_error(doc(30, {k(0), {{"weights", json::object()}}}));
  EXPECT_HAS(msg, "keyframe 1: 'time' is missing");
  msg = file_error(doc(30, {k(0), {{"time", "1"}, {"weights", json::object()}}}));
  EXPECT_HAS(msg, "keyframe 1: 'time' is not a number");
  msg = file_error(doc(30, {k(0), {{"time", 1.0}}}));
  EXPECT_HAS(msg, "keyframe 1: 'weights' is missing");
  msg = file_error(doc(30, {k(0), 5}));
  EXPECT_HAS(msg, "keyframe 1: is not an object");
  // JSON text cannot hold NaN or infinity, but a json built in code can.
  for (double t : {std::nan(""), std::numeric_limits<double>::infinity()}) {
    msg = error_of([&] { performance_from_json(doc(30, {k(0), k(t)}), kNames, "ctx"); });
    EXPECT_HAS(msg, "ctx: keyframe 1: time is");
    EXPECT_HAS(msg, "must be finite");
  }
  msg = file_error(doc(30, {k(0), k(1e9)}));
  EXPECT_HAS(msg, "frames at 30 fps");
  // The bound is two hours at 30 fps (perf_limits.h): a 60-byte file must not
  // make the reader allocate gigabytes.
  msg = file_error(doc(30, {k(0), k(7300)}));
  EXPECT_HAS(msg, "more than 216000 frames at 30 fps");
}

TEST_F(PerformanceFiles, WeightErrors) {
  auto k = [](double t, json weights) { return json{{"time", t}, {"weights", weights}}; };
  std::string msg = file_error(doc(30, {k(0, json::object()), k(1, {{"jawOpn", 0.5}})}));
  EXPECT_HAS(msg, "keyframe 1: unknown blendshape 'jawOpn'");
  EXPECT_HAS(msg, "e.g. jawOpen, mouthSmile_L");
  msg = file_error(doc(30, {k(0, {{"JAWOPEN", 0.5}})}));
  EXPECT_HAS(msg, "did you mean 'jawOpen'");
  for (double v : {1.5, -0.1}) {
    msg = file_error(doc(30, {k(0, json::object()), k(1, json::object()), k(2, {{"mouthSmile_R", v}})}));
    EXPECT_HAS(msg, "keyframe 2: weight 'mouthSmile_R'");
    EXPECT_HAS(msg, "outside [0, 1]");
  }
  msg = file_error(doc(30, {k(0, {{"jawOpen", "high"}})}));
  EXPECT_HAS(msg, "keyframe 0: weight 'jawOpen' is not a number");
  msg = file_error(doc(30, {k(0, {{"jawOpen", true}})}));
  EXPECT_HAS(msg, "keyframe 0: weight 'jawOpen' is not a number");
  msg = error_of([&] { performance_from_json(doc(30, {k(0, {{"jawOpen", std::nan("")}})}), kNames, "p.json"); });
  EXPECT_HAS(msg, "p.json: keyframe 0: weight 'jawOpen' is NaN");
  msg = error_of([&] {
    performance_from_json(doc(30, {k(0, {{"jawOpen", -std::numeric_limits<double>::infinity()}})}), kNames, "p.json");
  });
  EXPECT_HAS(msg, "p.json: keyframe 0: weight 'jawOpen' is infinite");
  // 0 and 1 themselves are fine.
  EXPECT_NO_THROW(performance_from_json(doc(30, {k(0, {{"jawOpen", 0}, {"mouthSmile_L", 1}})}), kNames, "x"));
}

TEST_F(PerformanceFiles, JsonRoundTripIsBitExact) {
  const std::vector<std::string> names = procedural_names();
  for (const std::string builtin : {"talk", "random"}) {
    Performance p = builtin_performance(builtin, names);
    p.start_time = 0.25;  // also a start off zero
    const std::string path = (dir_ / (builtin + ".json")).string();
    save_performance_json(p, path);
    const Performance q = load_performance_json(path, names);
    EXPECT_EQ(q.name, p.name);
    EXPECT_EQ(q.fps, p.fps);
    EXPECT_EQ(q.start_time, p.start_time);
    EXPECT_EQ(q.names, p.names);
    ASSERT_EQ(q.frames(), p.frames());
    EXPECT_TRUE(q.weights == p.weights) << builtin << ": weights differ after the round trip";
    // The file is readable JSON in the documented format.
    std::ifstream in(path);
    const json j = json::parse(in);
    EXPECT_EQ(j["format"], "facesr-performance");
    EXPECT_EQ(j["version"], 1);
    EXPECT_EQ(j["keyframes"].size(), size_t(p.frames()));
  }
  // A failed save leaves nothing behind.
  const Performance p = builtin_performance("jaw", names);
  const fs::path bad = dir_ / "no_such_dir" / "jaw.json";
  EXPECT_THROW(save_performance_json(p, bad.string()), Error);
  EXPECT_FALSE(fs::exists(bad));
}

TEST(PerformanceBuiltins, InRangeNonConstantAndStartNeutral) {
  const std::vector<std::string> names = procedural_names();
  const std::vector<std::string> builtins = builtin_performance_names();
  for (const char* expected : {"smile", "jaw", "talk", "random"})
    EXPECT_NE(std::find(builtins.begin(), builtins.end(), expected), builtins.end()) << expected;
  for (const std::string& b : builtins) {
    const Performance p = builtin_performance(b, names);
    EXPECT_EQ(p.name, b);
    EXPECT_EQ(p.fps, 30);
    EXPECT_EQ(p.names, names);
    ASSERT_GT(p.frames(), 30) << b;
    for (float v : p.weights) ASSERT_TRUE(v >= 0 && v <= 1) << b << ": weight " << v;
    for (size_t s = 0; s < names.size(); ++s) EXPECT_EQ(p.frame(0)[s], 0.0f) << b << " " << names[s];
    const std::vector<float> mx = max_weights(p);
    // "subtle" and "nudge" are small on purpose (poses up to 0.36 and 0.08).
    const bool small = b == "subtle" || b == "nudge";
    EXPECT_GT(*std::max_element(mx.begin(), mx.end()), small ? 0.05f : 0.3f) << b << " does not move";
  }
  const Performance smile = builtin_performance("smile", names);
  EXPECT_EQ(smile.frames(), 61);
  EXPECT_FLOAT_EQ(w(smile, 30, "mouthSmile_L"), 1.0f);
  EXPECT_FLOAT_EQ(w(smile, 30, "mouthSmile_R"), 1.0f);
  EXPECT_FLOAT_EQ(w(smile, 15, "mouthSmile_L"), 0.5f);
  EXPECT_EQ(w(smile, 60, "mouthSmile_L"), 0.0f);
  EXPECT_EQ(max_weights(smile)[index_of(smile, "jawOpen")], 0.0f);
  const Performance jaw = builtin_performance("jaw", names);
  EXPECT_FLOAT_EQ(w(jaw, 30, "jawOpen"), 1.0f);
  EXPECT_EQ(max_weights(jaw)[index_of(jaw, "mouthSmile_L")], 0.0f);

  const Performance talk = builtin_performance("talk", names);
  const std::vector<float> tm = max_weights(talk);
  for (const char* s : {"jawOpen", "mouthFunnel", "mouthPucker", "mouthSmile_L", "mouthSmile_R", "browInnerUp_L"})
    EXPECT_GT(tm[index_of(talk, s)], 0.2f) << s;
  EXPECT_EQ(tm[index_of(talk, "cheekPuff_L")], 0.0f);

  // Random: every shape moves; deterministic; a shape's curve does not depend on the rig's order.
  const Performance r = builtin_performance("random", names);
  for (size_t s = 0; s < names.size(); ++s) EXPECT_GT(max_weights(r)[s], 0.2f) << names[s];
  EXPECT_TRUE(builtin_performance("random", names).weights == r.weights);
  std::vector<std::string> reversed(names.rbegin(), names.rend());
  const Performance rr = builtin_performance("random", reversed);
  for (int f = 0; f < r.frames(); f += 7) EXPECT_EQ(w(rr, f, "noseSneer_L"), w(r, f, "noseSneer_L"));

  // Sparse: at each pose (every 12 frames) 2 to 5 base shapes (4 to 10 rig
  // shapes with halves) are on and the rest off; over the take many shapes
  // move; deterministic and independent of the rig's order.
  std::vector<std::string> ict = {"jawForward", "jawLeft", "jawOpen", "jawRight", "mouthClose", "mouthFunnel",
                                  "mouthLeft", "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper",
                                  "mouthShrugLower", "mouthShrugUpper"};
  for (const char* base : {"browDown", "browInnerUp", "browOuterUp", "cheekPuff", "cheekSquint", "eyeBlink",
                           "eyeLookDown", "eyeLookIn", "eyeLookOut", "eyeLookUp", "eyeSquint", "eyeWide",
                           "mouthDimple", "mouthFrown", "mouthLowerDown", "mouthPress", "mouthSmile", "mouthStretch",
                           "mouthUpperUp", "noseSneer"})
    for (const char* side : {"_L", "_R"}) ict.push_back(std::string(base) + side);
  ASSERT_EQ(ict.size(), 53u);  // the ICT head's (and ARKit's) 53 shapes
  const Performance sp = builtin_performance("sparse", ict);
  EXPECT_EQ(sp.frames(), 121);
  for (int f = 12; f < sp.frames(); f += 12) {
    int on = 0;
    for (size_t s = 0; s < ict.size(); ++s) on += sp.frame(f)[s] > 0;
    EXPECT_GE(on, 2) << "frame " << f;
    EXPECT_LE(on, 10) << "frame " << f;
  }
  const std::vector<float> sm = max_weights(sp);
  EXPECT_GE(std::count_if(sm.begin(), sm.end(), [](float v) { return v > 0.3f; }), 15);
  EXPECT_TRUE(builtin_performance("sparse", ict).weights == sp.weights);
  const Performance spr = builtin_performance("sparse", std::vector<std::string>(ict.rbegin(), ict.rend()));
  for (int f = 0; f < sp.frames(); f += 5)
    for (const char* n : {"jawOpen", "mouthSmile_L", "browInnerUp_R"}) EXPECT_EQ(w(spr, f, n), w(sp, f, n)) << n;

  // Other takes of the same kind: named for their number, other poses, the
  // same rules, deterministic.
  const Performance s2 = builtin_performance("sparse-2", ict), s3 = builtin_performance("sparse-3", ict);
  EXPECT_EQ(s2.name, "sparse-2");
  EXPECT_EQ(s2.frames(), sp.frames());
  EXPECT_FALSE(s2.weights == sp.weights);
  EXPECT_FALSE(s2.weights == s3.weights);
  EXPECT_TRUE(builtin_performance("sparse-2", ict).weights == s2.weights);
  for (int f = 12; f < s2.frames(); f += 12) {
    int on = 0;
    for (size_t s = 0; s < ict.size(); ++s) on += s2.frame(f)[s] > 0;
    EXPECT_GE(on, 2) << "frame " << f;
    EXPECT_LE(on, 10) << "frame " << f;
  }
  for (const char* bad : {"sparse-1", "sparse-0", "sparse-100", "sparse-x", "sparse-"})
    EXPECT_HAS(error_of([&] { builtin_performance(bad, ict); }), std::string("'") + bad + "'");

  // Subtle: small poses (1 to 3 bases, at most 0.3 × 1.2) every 0.6 s at odd
  // controls (frames 9, 27, ...), neutral at even ones (0, 18, ...), so many
  // frames lie just off rest; deterministic and independent of the rig's order.
  const Performance su = builtin_performance("subtle", ict);
  EXPECT_EQ(su.frames(), 181);
  for (float v : su.weights) EXPECT_LE(v, 0.36f + 1e-6f);
  for (int f = 0; f < su.frames(); f += 18)
    for (size_t s = 0; s < ict.size(); ++s) EXPECT_LT(su.frame(f)[s], 1e-6f) << "frame " << f << " " << ict[s];
  for (int f = 9; f < su.frames(); f += 18) {
    int on = 0;
    for (size_t s = 0; s < ict.size(); ++s) on += su.frame(f)[s] >= 0.016f;  // 0.02 × 0.8
    EXPECT_GE(on, 1) << "frame " << f;
    EXPECT_LE(on, 6) << "frame " << f;
  }
  int near_rest = 0;
  for (int f = 0; f < su.frames(); ++f) {
    const float* x = su.frame(f);
    const float m = *std::max_element(x, x + ict.size());
    near_rest += m > 0 && m < 0.02f;
  }
  EXPECT_GE(near_rest, 20);
  EXPECT_TRUE(builtin_performance("subtle", ict).weights == su.weights);
  const Performance sur = builtin_performance("subtle", std::vector<std::string>(ict.rbegin(), ict.rend()));
  for (int f = 0; f < su.frames(); f += 3)
    for (size_t s = 0; s < ict.size(); s += 5) EXPECT_EQ(w(sur, f, ict[s]), w(su, f, ict[s]));
}

TEST(PerformanceBuiltins, NudgeMovesEachShapeAloneAtThreeSmallWeights) {
  const std::vector<std::string> names = procedural_names();
  const Performance p = builtin_performance("nudge", names);
  ASSERT_EQ(p.frames(), int(1 + 3 * names.size()));
  for (size_t s = 0; s < names.size(); ++s) EXPECT_EQ(p.frame(0)[s], 0.0f);
  for (size_t s = 0; s < names.size(); ++s) {
    const float expected[3] = {0.005f, 0.02f, 0.08f};
    for (int k = 0; k < 3; ++k) {
      const float* x = p.frame(int(1 + 3 * s + k));
      for (size_t o = 0; o < names.size(); ++o)
        EXPECT_EQ(x[o], o == s ? expected[k] : 0.0f) << "frame " << 1 + 3 * s + k << " shape " << names[o];
    }
  }
}

TEST(PerformanceBuiltins, MissingShapesAreSkippedAndUnknownNamesListed) {
  const Performance p = builtin_performance("smile", {"jawOpen", "somethingElse"});
  EXPECT_EQ(p.frames(), 61);
  for (float v : p.weights) EXPECT_EQ(v, 0.0f);
  // ARKit-style names are recognised too.
  const Performance a = builtin_performance("smile", {"mouthSmileLeft", "mouthSmileRight"});
  EXPECT_FLOAT_EQ(a.frame(30)[0], 1.0f);
  EXPECT_FLOAT_EQ(a.frame(30)[1], 1.0f);
  const std::string msg = error_of([] { builtin_performance("frown", kNames); });
  EXPECT_HAS(msg, "'frown'");
  for (const char* n : {"smile", "jaw", "talk", "random", "sparse-2"}) EXPECT_HAS(msg, n);
}
