// The runtime a game drives: synchronous and pipelined stepping give the
// same surfaces, contexts sharing a rig and a model agree, controls are
// validated, and external forces move the face.
#include <gtest/gtest.h>

#include <memory>

#include "perf/performance.h"
#include "rig/rig_io.h"
#include "compute/cl_device.h"
#include "runtime/runtime_context.h"
#include "runtime/runtime_model.h"
#include "runtime/sr_inference.h"
#include "sr_fixtures.h"
#include "test_support.h"

namespace facesr {
namespace {

struct RuntimeFixture : ::testing::Test {
  static void SetUpTestSuite() {
    rig_ = std::make_shared<const Rig>(fixtures::procedural_rig());
    model_ = fixtures::random_model();
  }
  static std::vector<std::vector<float>> weights(int F) {
    const Performance p = builtin_performance("talk", rig_->blendshape_names);
    std::vector<std::vector<float>> w;
    for (int f = 0; f < F; ++f) w.emplace_back(p.frame(10 + f), p.frame(10 + f) + p.names.size());
    return w;
  }
  static inline std::shared_ptr<const Rig> rig_;
  static inline std::shared_ptr<const SrModel> model_;
};

TEST_F(RuntimeFixture, AsyncSteppingGivesTheSyncSurfacesOneFrameLate) {
  const auto w = weights(6);
  RuntimeContext sync(rig_, model_), async(rig_, model_);
  std::vector<std::vector<float>> a, b;
  for (const auto& f : w) {
    sync.set_weights(f);
    sync.step();
    a.push_back(sync.result().positions);
  }
  int64_t expect = 0;
  for (const auto& f : w) {
    async.set_weights(f);
    async.step_async();
    if (async.pending() == 2) {
      EXPECT_EQ(async.wait(), expect++);
      b.push_back(async.result().positions);
    }
  }
  while (async.pending() > 0) {
    EXPECT_EQ(async.wait(), expect++);
    b.push_back(async.result().positions);
  }
  ASSERT_EQ(a.size(), b.size());
  for (size_t f = 0; f < a.size(); ++f) EXPECT_EQ(a[f], b[f]) << "frame " << f;
  // The face moved: the surfaces are not the rest pose.
  double moved = 0;
  for (size_t i = 0; i < a.back().size(); ++i) moved = std::max(moved, double(std::abs(a.back()[i] - rig_->surface.data()[i])));
  EXPECT_GT(moved, 1e-3);
}

// split_device: the simulation and the inference on half the device each
// (sub-devices where the device allows it) give the same surfaces, pipelined,
// as the whole device stepping synchronously.
TEST_F(RuntimeFixture, SplitDevicePipelinedGivesTheSameSurfaces) {
  const auto w = weights(4);
  RuntimeOptions split_opt;
  split_opt.split_device = true;
  RuntimeContext whole(rig_, model_), split(rig_, model_, split_opt);
  std::printf("split: %s\n", split.device().c_str());
  if (compute::select_device().compute_units >= 2)
    EXPECT_NE(split.device().find("part 1 of 2"), std::string::npos) << split.device();
  std::vector<std::vector<float>> a, b;
  for (const auto& f : w) {
    whole.set_weights(f);
    whole.step();
    a.push_back(whole.result().positions);
    split.set_weights(f);
    split.step_async();
    if (split.pending() == 2) {
      split.wait();
      b.push_back(split.result().positions);
    }
  }
  while (split.pending() > 0) {
    split.wait();
    b.push_back(split.result().positions);
  }
  ASSERT_EQ(a.size(), b.size());
  for (size_t f = 0; f < a.size(); ++f) EXPECT_EQ(a[f], b[f]) << "frame " << f;
}

// The LR simulation in float (the default) and in double: the same
// surfaces to far below the network's error, and the device says which.
TEST_F(RuntimeFixture, FloatAndDoubleSimulationsAgree) {
  const auto w = weights(4);
  RuntimeOptions dbl;
  dbl.lr_single_precision = false;
  RuntimeContext f32(rig_, model_), f64(rig_, model_, dbl);
  // device(): the simulation's, then " + " and the inference's (always float).
  const auto sim = [](const RuntimeContext& c) { return c.device().substr(0, c.device().find(" + ")); };
  EXPECT_NE(sim(f32).find("(OpenCL, float)"), std::string::npos) << f32.device();
  EXPECT_NE(sim(f64).find("(OpenCL, double)"), std::string::npos) << f64.device();
  double worst = 0, moved = 0;
  for (const auto& f : w) {
    f32.set_weights(f);
    f64.set_weights(f);
    f32.step();
    f64.step();
    const auto &a = f32.result().embedded, &b = f64.result().embedded;
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) worst = std::max(worst, double(std::abs(a[i] - b[i])));
    for (size_t i = 0; i < a.size(); ++i) moved = std::max(moved, double(std::abs(a[i] - rig_->surface.data()[i])));
  }
  std::printf("float vs double: max embedded difference %.2e cm (largest motion %.3f cm)\n", worst, moved);
  EXPECT_GT(moved, 1e-2);
  EXPECT_LT(worst, 1e-3);
}

TEST_F(RuntimeFixture, TwoContextsSharingARigAndModelAgree) {
  const auto w = weights(4);
  RuntimeContext c1(rig_, model_), c2(rig_, model_);
  for (const auto& f : w) {
    c1.set_weights(f);
    c2.set_weights(f);
    c1.step();
    c2.step();
    EXPECT_EQ(c1.result().positions, c2.result().positions);
    EXPECT_EQ(c1.result().embedded, c2.result().embedded);
  }
  EXPECT_EQ(c1.result().frame, 3);
  // Normals are unit length.
  const auto& n = c1.result().normals;
  for (size_t v = 0; v < n.size(); v += 3) {
    const double len = std::sqrt(n[v] * n[v] + n[v + 1] * n[v + 1] + n[v + 2] * n[v + 2]);
    if (len > 0) EXPECT_NEAR(len, 1, 1e-5);
  }
}

TEST_F(RuntimeFixture, ContextsOnOneCompiledModelShareItAndMatchOnesThatCompiledTheirOwn) {
  const std::shared_ptr<const RuntimeModel> compiled = compile_runtime_model(rig_, model_);
  RuntimeContext a(compiled), b(compiled), own(rig_, model_);
  EXPECT_EQ(a.compiled(), compiled);
  EXPECT_EQ(b.compiled(), compiled);
  EXPECT_NE(own.compiled(), compiled);
  EXPECT_EQ(compiled.use_count(), 3);  // this test's and the two contexts'
  for (const auto& f : weights(3)) {
    for (RuntimeContext* c : {&a, &b, &own}) {
      c->set_weights(f);
      c->step();
    }
    EXPECT_EQ(a.result().positions, own.result().positions);
    EXPECT_EQ(b.result().positions, own.result().positions);
    EXPECT_EQ(a.result().embedded, own.result().embedded);
  }
  // The plan and the LR model are the shared ones, not copies.
  EXPECT_EQ(compiled->plan->M, model_->num_hr);
  EXPECT_EQ(compiled->hr_rest.size(), size_t(3 * rig_->num_surface_vertices()));
}

TEST_F(RuntimeFixture, CompilingAModelWithAnotherRigIsAnError) {
  auto other = std::make_shared<Rig>(*rig_);
  other->surface(0, 0) += 0.5;  // same sizes, another rig
  EXPECT_NE(fixtures::error_of([&] { compile_runtime_model(other, model_); }).find("rig"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { compile_runtime_model(nullptr, model_); }).find("a rig and a model"),
            std::string::npos);
  // A plan made for another model is refused by both inferences.
  auto plan = std::make_shared<SrInferencePlan>(make_inference_plan(*model_));
  plan->M += 1;
  EXPECT_NE(fixtures::error_of([&] { make_cpu_inference(model_, plan); }).find("another model"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { make_cl_inference(model_, {}, plan); }).find("another model"), std::string::npos);
}

TEST_F(RuntimeFixture, CpuAndOpenClInferenceAgree) {
  RuntimeOptions cpu;
  cpu.cpu_inference = true;
  RuntimeContext a(rig_, model_), b(rig_, model_, cpu);
  for (const auto& f : weights(2)) {
    a.set_weights(f);
    b.set_weights(f);
    a.step();
    b.step();
  }
  double worst = 0;
  for (size_t i = 0; i < a.result().positions.size(); ++i)
    worst = std::max(worst, double(std::abs(a.result().positions[i] - b.result().positions[i])));
  EXPECT_LT(worst, 1e-4);
}

TEST_F(RuntimeFixture, ControlsAreValidatedAndErrorsLeaveTheContextUsable) {
  RuntimeContext c(rig_, model_);
  EXPECT_NE(fixtures::error_of([&] { c.set_weight(0, std::nanf("")); }).find("not finite"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.set_weight(0, 1.5f); }).find("outside [-0.1, 1.1]"), std::string::npos);
  // Capture overshoots within the tolerance are clamped, like the Live Link import's.
  EXPECT_NO_THROW(c.set_weight(0, 1.08f));
  EXPECT_NO_THROW(c.set_weights(std::vector<float>(size_t(c.num_weights()), -0.05f)));
  c.reset();
  c.set_weight(0, 1.08f);
  c.step();
  const std::vector<float> over = c.result().positions;
  c.reset();
  c.set_weight(0, 1.0f);
  c.step();
  EXPECT_EQ(c.result().positions, over);  // 1.08 was taken as 1
  c.reset();
  EXPECT_NE(fixtures::error_of([&] { c.set_weight(-1, 0.5f); }).find("out of range"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.set_weight("noSuchShape", 0.5f); }).find("noSuchShape"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.set_weights({0.5f}); }).find("weights given"), std::string::npos);
  Mat3 shear = Mat3::Identity();
  shear(0, 1) = 0.5;
  EXPECT_NE(fixtures::error_of([&] { c.set_jaw(shear, Vec3::Zero()); }).find("rotation"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.wait(); }).find("no frame is pending"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.add_spring(-3, Vec3::Zero(), 1); }).find("out of range"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.add_sphere(Vec3::Zero(), -1, 1); }).find("radius"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.move_spring(99, Vec3::Zero()); }).find("no spring"), std::string::npos);
  c.step_async();
  c.step_async();
  EXPECT_NE(fixtures::error_of([&] { c.step_async(); }).find("already pending"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { c.step(); }).find("pending"), std::string::npos);
  EXPECT_EQ(c.wait(), 0);
  EXPECT_EQ(c.wait(), 1);
  c.set_weight("jawOpen", 0.6f);
  c.step();
  EXPECT_EQ(c.result().frame, 2);
  c.reset();
  EXPECT_EQ(c.result().frame, -1);
  for (long i = 0; i < rig_->surface.size(); ++i) EXPECT_EQ(c.result().positions[size_t(i)], float(rig_->surface.data()[i]));
}

TEST_F(RuntimeFixture, ASpringPullsTheFaceAndRemovingItLetsGo) {
  RuntimeContext free_face(rig_, model_), pulled(rig_, model_);
  int corner = -1;
  for (size_t i = 0; i < rig_->landmark_names.size(); ++i)
    if (rig_->landmark_names[i] == "mouth_corner_L") corner = rig_->landmark_vertex[i];
  ASSERT_GE(corner, 0);
  const Vec3 rest = rig_->surface.row(corner).transpose();
  const int id = pulled.add_spring(corner, rest + Vec3(1.0, -0.5, 0.5), 200);
  free_face.step();
  pulled.step();
  auto at = [&](const RuntimeContext& c) {
    const auto& e = c.result().embedded;
    return Vec3(e[3 * corner], e[3 * corner + 1], e[3 * corner + 2]);
  };
  EXPECT_GT((at(pulled) - at(free_face)).norm(), 0.05) << "the spring should move the lip corner";
  pulled.remove_spring(id);
  EXPECT_NE(fixtures::error_of([&] { pulled.remove_spring(id); }).find("no spring"), std::string::npos);
  const int s = pulled.add_sphere(rest + Vec3(0, 0, 2), 1.0, 100);
  EXPECT_GT(s, id);
  pulled.move_sphere(s, rest + Vec3(0, 0, 3));
  pulled.remove_sphere(s);
}

TEST_F(RuntimeFixture, AModelOfAnotherRigIsRefused) {
  auto other = std::make_shared<SrModel>(*model_);
  other->rig_checksum ^= 1;
  const std::string e = fixtures::error_of([&] { RuntimeContext c(rig_, other); });
  EXPECT_NE(e.find("was trained on rig"), std::string::npos) << e;
}

}  // namespace
}  // namespace facesr
