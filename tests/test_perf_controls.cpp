// The optional explicit jaw of a performance: keyframe parsing and
// interpolation, its validation, the JSON round trip, and frame_controls
// turning it into a rigid transform about the rig's jaw pivot.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "perf/perf_controls.h"
#include "perf/performance.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;
using fixtures::error_of;
using nlohmann::json;

namespace {

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

const std::vector<std::string> kNames = {"jawOpen", "mouthSmile_L", "mouthSmile_R"};

json key(double t, double open, json jaw) {
  json k = {{"time", t}, {"weights", {{"jawOpen", open}}}};
  if (!jaw.is_null()) k["jaw"] = std::move(jaw);
  return k;
}

json doc(json keyframes) {
  return {{"format", "facesr-performance"}, {"version", 1}, {"fps", 10}, {"keyframes", std::move(keyframes)}};
}

json jaw(std::vector<double> r, std::vector<double> t) { return {{"rotation_deg", r}, {"translation_cm", t}}; }

}  // namespace

TEST(PerformanceJaw, KeyframesInterpolateAndRoundTrip) {
  const json j = doc({key(0, 0, jaw({0, 0, 0}, {0, 0, 0})), key(1, 0.5, jaw({20, 0, -4}, {0, -0.2, 0.3})),
                      key(1.5, 0, jaw({10, 0, 0}, {0, 0, 0}))});
  const Performance p = performance_from_json(j, kNames, "jaw.json");
  ASSERT_TRUE(p.has_jaw);
  ASSERT_EQ(p.frames(), 16);
  ASSERT_EQ(p.jaw.size(), 16u * 6);
  EXPECT_FLOAT_EQ(p.jaw_frame(5)[0], 10.0f);  // halfway to the second keyframe
  EXPECT_FLOAT_EQ(p.jaw_frame(5)[2], -2.0f);
  EXPECT_FLOAT_EQ(p.jaw_frame(5)[4], -0.1f);
  EXPECT_EQ(p.jaw_frame(10)[0], 20.0f);  // on a keyframe: exact
  EXPECT_EQ(p.jaw_frame(10)[5], 0.3f);
  EXPECT_FLOAT_EQ(p.jaw_frame(15)[0], 10.0f);

  const fs::path path = fs::temp_directory_path() / ("facesr_jaw_" + std::to_string(::getpid()) + ".json");
  save_performance_json(p, path.string());
  const Performance q = load_performance_json(path.string(), kNames);
  fs::remove(path);
  EXPECT_TRUE(q.has_jaw);
  EXPECT_TRUE(q.jaw == p.jaw);
  EXPECT_TRUE(q.weights == p.weights);
  const json out = performance_to_json(p);
  EXPECT_EQ(out["keyframes"][10]["jaw"]["rotation_deg"], json({20, 0, -4}));

  // Files without "jaw" stay jawless, and a missing member is zero.
  EXPECT_FALSE(performance_from_json(doc({key(0, 0, nullptr)}), kNames, "x").has_jaw);
  EXPECT_FALSE(performance_to_json(performance_from_json(doc({key(0, 0, nullptr)}), kNames, "x"))["keyframes"][0]
                   .contains("jaw"));
  const Performance r = performance_from_json(doc({key(0, 0, {{"translation_cm", {0, 0, 1}}})}), kNames, "x");
  EXPECT_EQ(r.jaw, (std::vector<float>{0, 0, 0, 0, 0, 1}));
}

TEST(PerformanceJaw, ValidationErrors) {
  auto err = [](json keyframes) {
    return error_of([&] { performance_from_json(doc(std::move(keyframes)), kNames, "p.json"); });
  };
  const json ok = jaw({0, 0, 0}, {0, 0, 0});
  std::string msg = err({key(0, 0, ok), key(1, 0, nullptr)});
  EXPECT_HAS(msg, "p.json: keyframe 1 has no 'jaw' but keyframe 0 has one");
  msg = err({key(0, 0, nullptr), key(1, 0, nullptr), key(2, 0, ok)});
  EXPECT_HAS(msg, "p.json: keyframe 2 has a 'jaw' but keyframe 0 has none");
  EXPECT_HAS(err({key(0, 0, jaw({61, 0, 0}, {0, 0, 0}))}), "keyframe 0: jaw 'rotation_deg' has length 61 degrees");
  EXPECT_HAS(err({key(0, 0, jaw({0, 0, 0}, {3, 4, 0.5}))}), "jaw 'translation_cm' has length");
  EXPECT_HAS(err({key(0, 0, jaw({0, 0, 0}, {0, 0, std::nan("")}))}), "jaw 'translation_cm'[2] is NaN");
  EXPECT_HAS(err({key(0, 0, {{"rotation_deg", {1, 2}}})}), "jaw 'rotation_deg' is not an array of 3 numbers");
  EXPECT_HAS(err({key(0, 0, {{"rotation_deg", {1, "2", 3}}})}), "jaw 'rotation_deg'[1] is not a number");
  EXPECT_HAS(err({key(0, 0, {{"rotation", {1, 2, 3}}})}), "'jaw' has unknown member 'rotation'");
  EXPECT_HAS(err({key(0, 0, 5)}), "keyframe 0: 'jaw' is not an object");
  // The bounds themselves are allowed.
  EXPECT_NO_THROW(performance_from_json(doc({key(0, 0, jaw({0, 60, 0}, {0, -5, 0}))}), kNames, "x"));
}

TEST(PerformanceJaw, FrameControlsRotateAboutThePivot) {
  Jaw rig_jaw;
  rig_jaw.pivot = Vec3(0.5, -3.0, 2.0);
  const json j = doc({key(0, 0.2, jaw({12, -5, 3}, {0.1, -0.3, 0.2})), key(1, 0.4, jaw({0, 0, 0}, {0, 0, 0}))});
  const Performance p = performance_from_json(j, kNames, "x");
  Controls c;
  c.springs.push_back(PointSpring{3, Vec3(1, 2, 3), 7});
  c.spheres.push_back(SphereCollider{Vec3(0, 0, 9), 1.5, 20});
  frame_controls(p, 0, rig_jaw, c);
  EXPECT_EQ(c.weights, (std::vector<float>{0.2f, 0, 0}));
  ASSERT_TRUE(c.jaw_override);
  // R is a proper rotation by |r| = sqrt(144 + 25 + 9) degrees about r.
  EXPECT_LT((c.jaw_R * c.jaw_R.transpose() - Mat3::Identity()).norm(), 1e-12);
  EXPECT_NEAR(c.jaw_R.determinant(), 1.0, 1e-12);
  const Vec3 r_deg(12, -5, 3);
  EXPECT_NEAR(Eigen::AngleAxisd(c.jaw_R).angle(), r_deg.norm() * M_PI / 180, 1e-6);
  EXPECT_LT((c.jaw_R * r_deg - r_deg).norm(), 1e-6);  // the axis is fixed
  // The pivot only translates; a point off it turns about it.
  const Vec3 t(0.1, -0.3, 0.2);
  EXPECT_LT((c.jaw_R * rig_jaw.pivot + c.jaw_t - (rig_jaw.pivot + t)).norm(), 1e-6);
  const Vec3 x(1, -6, 7);
  EXPECT_LT((c.jaw_R * x + c.jaw_t - (rig_jaw.pivot + c.jaw_R * (x - rig_jaw.pivot) + t)).norm(), 1e-6);
  // External forces are untouched.
  ASSERT_EQ(c.springs.size(), 1u);
  EXPECT_EQ(c.springs[0].vertex, 3);
  ASSERT_EQ(c.spheres.size(), 1u);
  // The last frame has a zero jaw: identity.
  frame_controls(p, p.frames() - 1, rig_jaw, c);
  EXPECT_TRUE(c.jaw_override);
  EXPECT_LT((c.jaw_R - Mat3::Identity()).norm(), 1e-12);
  EXPECT_LT(c.jaw_t.norm(), 1e-12);
  EXPECT_FLOAT_EQ(c.weights[0], 0.4f);

  // Without an explicit jaw the override is off (even if it was on).
  const Performance plain = builtin_performance("jaw", kNames);
  frame_controls(plain, 30, rig_jaw, c);
  EXPECT_FALSE(c.jaw_override);
  EXPECT_FLOAT_EQ(c.weights[0], 1.0f);
  EXPECT_HAS(error_of([&] { frame_controls(plain, plain.frames(), rig_jaw, c); }), "outside [0, 61)");
}

// With the procedural rig's own jaw: its pivot stays put under a pure rotation.
TEST(PerformanceJaw, FrameControlsUseTheRigPivot) {
  const Rig& rig = fixtures::procedural_rig();
  Performance p;
  p.names = rig.blendshape_names;
  p.weights.assign(p.names.size(), 0.0f);
  p.has_jaw = true;
  p.jaw = {float(rig.jaw.axis.x() * 15), float(rig.jaw.axis.y() * 15), float(rig.jaw.axis.z() * 15), 0, 0, 0};
  Controls c;
  frame_controls(p, 0, rig.jaw, c);
  EXPECT_LT((c.jaw_R * rig.jaw.pivot + c.jaw_t - rig.jaw.pivot).norm(), 1e-5);
  EXPECT_NEAR(Eigen::AngleAxisd(c.jaw_R).angle(), 15 * M_PI / 180, 1e-5);
  EXPECT_EQ(c.weights.size(), rig.blendshape_names.size());
}
