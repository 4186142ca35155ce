// Divergence detection and the recovery ladder (sim/recovering_simulator.h):
// the ladder's logic on a scripted simulator, the criteria, and the real
// simulators (CPU and OpenCL) on a jaw thrown out of reach.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/block_model.h"
#include "sim/cl_simulator.h"
#include "sim/cpu_forces.h"
#include "sim/recovering_simulator.h"
#include "sim/sim_model.h"
#include "test_support.h"

using namespace facesr;

namespace {

// A stand-in solver whose "state" is the weight it last reached (stored in
// node 0's x): a step converges when the weight moves by at most `reach`
// and blows up (non-finite residual, NaN positions) otherwise; weights above
// `ceiling` always blow up. Weights at or below `near_rest` are reached only
// from the rest state (anywhere else Newton stalls, sane but far from
// equilibrium: residual 5), as a frame near rest after an extreme one does.
class ScriptedSimulator final : public Simulator {
 public:
  ScriptedSimulator(const SimModel& m, double reach, double ceiling, double near_rest = -1)
      : m_(m), reach_(reach), ceiling_(ceiling), near_rest_(near_rest) {
    reset();
  }
  StepStats step(const Controls& c) override {
    ++steps;
    StepStats st;
    const double w = c.weights.at(0);
    if (w <= near_rest_ && x_[0] != 0) {
      st.rel_residual = 5;
    } else if (std::abs(w - x_[0]) <= reach_ && w <= ceiling_) {
      x_[0] = w;
      st.converged = true;
      st.rel_residual = 1e-4;
      st.status = StepStatus::Converged;
    } else {
      x_[0] = std::nan("");
      st.rel_residual = std::nan("");
      st.finite = false;
    }
    st.energy = 0;
    return st;
  }
  void reset() override { x_.assign(3 * size_t(m_.num_nodes), 0.0), x_[0] = 0; }
  void nodes(std::vector<double>& x) const override { x = x_; }
  void surface(std::vector<double>& s) const override { s.assign(3, x_[0]); }
  void set_nodes(const std::vector<double>& x) override { x_ = x; }
  void forces(const Controls&, std::vector<double>& f) override { f.assign(x_.size(), 0.0); }
  std::string device() const override { return "scripted"; }
  double time_stiffness_product(int) override { return 0; }
  const SimModel& model() const override { return m_; }
  const SolverOptions& options() const override { return opt_; }
  void set_options(const SolverOptions& o) override { opt_ = o; }
  int steps = 0;

 private:
  SimModel m_;
  SolverOptions opt_;
  std::vector<double> x_;
  double reach_, ceiling_, near_rest_;
};

Controls weight(const SimModel& m, float w) {
  Controls c;
  c.weights.assign(size_t(m.num_shapes), 0.0f);
  c.weights[0] = w;
  return c;
}

// x_[0] is the weight; the rest of the block's nodes stay at 0, so rest-pose
// inversion counts do not matter here.
SimModel block() { return make_block_model(2, 2, 2, 1.0); }

}  // namespace

TEST(SimRecovery, AFrameThatSolvesFirstTimePassesThrough) {
  const SimModel m = block();
  auto raw = std::make_unique<ScriptedSimulator>(m, 0.5, 1.0);
  ScriptedSimulator* inner = raw.get();
  auto sim = make_recovering_simulator(std::move(raw));
  const StepStats st = sim->step(weight(m, 0.3f));
  EXPECT_EQ(st.status, StepStatus::Converged);
  EXPECT_EQ(st.recoveries, 0);
  EXPECT_EQ(inner->steps, 1);
  std::vector<double> x;
  sim->nodes(x);
  EXPECT_FLOAT_EQ(float(x[0]), 0.3f);
}

TEST(SimRecovery, AJumpTooFarIsSolvedInSubSteps) {
  const SimModel m = block();
  auto raw = std::make_unique<ScriptedSimulator>(m, 0.3, 1.0);
  ScriptedSimulator* inner = raw.get();
  auto sim = make_recovering_simulator(std::move(raw));
  // 0 → 1 in one step fails, and again from the last good state; four
  // sub-steps of 0.25 each reach it.
  const StepStats st = sim->step(weight(m, 1.0f));
  EXPECT_EQ(st.status, StepStatus::Recovered);
  EXPECT_EQ(st.recoveries, 1 + 4);
  EXPECT_EQ(inner->steps, 1 + 1 + 4);
  std::vector<double> x;
  sim->nodes(x);
  EXPECT_FLOAT_EQ(float(x[0]), 1.0f);
  // The solver's options are back as they were.
  EXPECT_EQ(sim->options().newton_max, SolverOptions{}.newton_max);
}

TEST(SimRecovery, NeedsTheFinerSubStepsOfTheLastRung) {
  const SimModel m = block();
  auto sim = make_recovering_simulator(std::make_unique<ScriptedSimulator>(m, 0.2, 1.0));
  // Steps of 0.25 are too far, steps of 0.125 (twice the sub-steps) are not.
  const StepStats st = sim->step(weight(m, 1.0f));
  EXPECT_EQ(st.status, StepStatus::Recovered);
  EXPECT_EQ(st.recoveries, 1 + 1 + 8);  // restart, the first sub-step of rung 2 fails, 8 of rung 3
}

TEST(SimRecovery, WhenEveryRungFailsTheLastGoodStateStands) {
  const SimModel m = block();
  auto sim = make_recovering_simulator(std::make_unique<ScriptedSimulator>(m, 0.5, 0.8));
  ASSERT_EQ(sim->step(weight(m, 0.4f)).status, StepStatus::Converged);
  const StepStats st = sim->step(weight(m, 0.9f));  // above the ceiling: never solvable
  EXPECT_EQ(st.status, StepStatus::Diverged);
  EXPECT_FALSE(st.converged);
  EXPECT_GT(st.recoveries, 0);
  std::vector<double> x, s;
  sim->nodes(x);
  sim->surface(s);
  EXPECT_FLOAT_EQ(float(x[0]), 0.4f);  // the last good frame, not NaN
  EXPECT_FLOAT_EQ(float(s[0]), 0.4f);
  // And the next reachable frame plays on from there.
  EXPECT_EQ(sim->step(weight(m, 0.6f)).status, StepStatus::Converged);
}

TEST(SimRecovery, AFrameNearRestAfterAnExtremeOneIsSolvedFromRest) {
  const SimModel m = block();
  auto raw = std::make_unique<ScriptedSimulator>(m, 1.0, 1.0, 0.05);
  ScriptedSimulator* inner = raw.get();
  auto sim = make_recovering_simulator(std::move(raw));
  ASSERT_EQ(sim->step(weight(m, 1.0f)).status, StepStatus::Converged);
  // From 1 (and every sub-step's state on the way) 0.02 stalls; from rest it solves.
  const StepStats st = sim->step(weight(m, 0.02f));
  EXPECT_EQ(st.status, StepStatus::Recovered);
  EXPECT_EQ(st.recoveries, 1 + 4 + 8 + 1);  // restart, rung 2's 4 sub-steps, rung 3's 8, from rest
  std::vector<double> x;
  sim->nodes(x);
  EXPECT_FLOAT_EQ(float(x[0]), 0.02f);
  EXPECT_EQ(inner->steps, 1 + 1 + 1 + 4 + 8 + 1);
  EXPECT_EQ(sim->options().newton_max, SolverOptions{}.newton_max);
}

TEST(SimRecovery, CriteriaNameEveryWayAFrameBreaks) {
  const SimModel m = block();
  SolverOptions o;
  StepStats ok;
  ok.rel_residual = 0.5;
  ok.energy = 1;
  ok.inverted_tets = 0;
  EXPECT_FALSE(step_diverged(ok, m, o, 0));
  StepStats s = ok;
  s.finite = false;
  EXPECT_TRUE(step_diverged(s, m, o, 0));
  s = ok;
  s.energy = std::nan("");
  EXPECT_TRUE(step_diverged(s, m, o, 0));
  s = ok;
  s.rel_residual = 1.5;  // further from equilibrium than the rest pose
  EXPECT_TRUE(step_diverged(s, m, o, 0));
  s = ok;
  s.inverted_tets = 32;  // within the allowance (max(32, 2 % of the tets)) over rest
  EXPECT_FALSE(step_diverged(s, m, o, 0));
  s.inverted_tets = 33;
  EXPECT_TRUE(step_diverged(s, m, o, 0));
  EXPECT_FALSE(step_diverged(s, m, o, 5));  // counted against the inversions at rest
}

// The real solvers on a frame that cannot be solved: the jaw of the coarse
// procedural face thrown 3 m away (a block would just stretch: its whole top
// layer moves with the "jaw"). Both say Diverged and keep the last good state.
class SimRecoveryReal : public ::testing::TestWithParam<bool> {};

TEST_P(SimRecoveryReal, AJawThrownOutOfReachIsDivergedAndTheGoodStateKept) {
  const bool opencl = GetParam();
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  SolverOptions o = realtime_solver();
  std::unique_ptr<Simulator> sim;
  if (opencl) {
    try {
      sim = make_cl_simulator(m, o);
    } catch (const Error& e) {
      GTEST_SKIP() << "no OpenCL device: " << e.what();
    }
  } else {
    sim = make_cpu_simulator(m, o);
  }
  Controls c = weight(m, 0.5f);
  const StepStats good = sim->step(c);
  ASSERT_NE(good.status, StepStatus::Diverged);
  std::vector<double> x_good, x;
  sim->nodes(x_good);
  c.jaw_override = true;
  c.jaw_t = Vec3(0, 300, 0);
  const StepStats bad = sim->step(c);
  EXPECT_EQ(bad.status, StepStatus::Diverged) << "residual " << bad.rel_residual << ", inverted " << bad.inverted_tets;
  sim->nodes(x);
  EXPECT_EQ(x, x_good);
  c.jaw_override = false;
  EXPECT_NE(sim->step(c).status, StepStatus::Diverged);
}

INSTANTIATE_TEST_SUITE_P(CpuAndOpenCl, SimRecoveryReal, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "OpenCl" : "Cpu"; });
