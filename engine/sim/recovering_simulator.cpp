#include "sim/recovering_simulator.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "sim/cpu_forces.h"

namespace facesr {

bool step_diverged(const StepStats& st, const SimModel& m, const SolverOptions& opt, int rest_inverted) {
  if (!st.finite || !std::isfinite(st.rel_residual) || !std::isfinite(st.energy)) return true;
  if (st.rel_residual > opt.diverged_residual) return true;
  const int allowed = std::max(32, int(opt.diverged_inverted_fraction * m.num_tets));
  return st.inverted_tets > rest_inverted + allowed;
}

namespace {

// The controls a fraction s of the way from a to b. Jaw overrides are
// interpolated by slerp; springs and spheres are b's with their stiffness
// scaled by s (a spring that appears this frame is switched on gradually).
Controls lerp_controls(const Controls& a, const Controls& b, double s) {
  Controls c = b;
  const size_t n = std::min(a.weights.size(), b.weights.size());
  for (size_t i = 0; i < n; ++i) c.weights[i] = float((1 - s) * a.weights[i] + s * b.weights[i]);
  if (a.activations.size() == b.activations.size())
    for (size_t i = 0; i < b.activations.size(); ++i)
      c.activations[i] = float((1 - s) * a.activations[i] + s * b.activations[i]);
  if (b.jaw_override) {
    const Mat3 Ra = a.jaw_override ? a.jaw_R : Mat3::Identity();
    const Vec3 ta = a.jaw_override ? a.jaw_t : Vec3::Zero();
    const Eigen::Quaterniond qa(Ra), qb(b.jaw_R);
    c.jaw_R = qa.slerp(s, qb).toRotationMatrix();
    c.jaw_t = (1 - s) * ta + s * b.jaw_t;
  }
  for (auto& sp : c.springs) sp.stiffness *= s;
  for (auto& sp : c.spheres) sp.stiffness *= s;
  return c;
}

bool all_finite(const std::vector<double>& x) {
  for (double v : x)
    if (!std::isfinite(v)) return false;
  return true;
}

class RecoveringSimulator final : public Simulator {
 public:
  explicit RecoveringSimulator(std::unique_ptr<Simulator> inner) : s_(std::move(inner)) {
    const SimModel& m = s_->model();
    rest_inverted_ = count_inverted(m, m.rest);
    good_controls_.weights.assign(size_t(m.num_shapes), 0.0f);
    s_->nodes(good_);
  }

  StepStats step(const Controls& c) override {
    const SolverOptions base = s_->options();
    StepStats st = s_->step(c);  // validates c before touching the state
    if (accept(st, base)) return finish(st, false, c);
    int extra = 0;
    // 1. From the last good state, no extrapolation.
    s_->set_nodes(good_);
    st = s_->step(c);
    ++extra;
    if (accept(st, base)) return finish(st, true, c, extra);
    // 2. Sub-steps; 3. sub-steps with the accurate caps.
    for (int attempt = 0; attempt < 2; ++attempt) {
      SolverOptions o = base;
      int substeps = std::max(2, base.recovery_substeps);
      if (attempt == 1) {
        o.newton_max = std::max(base.newton_max, 40);
        o.cg_max = std::max(base.cg_max, 400);
        o.cg_tol = std::min(base.cg_tol, 1e-2);
        substeps *= 2;
        s_->set_options(o);
      }
      s_->set_nodes(good_);
      bool ok = true;
      for (int k = 1; k <= substeps && ok; ++k) {
        st = s_->step(lerp_controls(good_controls_, c, double(k) / substeps));
        ++extra;
        ok = accept(st, o);
      }
      s_->set_options(base);
      if (ok) return finish(st, true, c, extra);
    }
    // 4. From the rest pose, accurate caps. The residual is measured against
    // the rest pose's, so a frame near rest that follows an extreme one starts
    // far above 1 from the last good state and its sub-steps; from rest it
    // starts at 1. A quasistatic equilibrium does not depend on the path.
    {
      SolverOptions o = base;
      o.newton_max = std::max(base.newton_max, 40);
      o.cg_max = std::max(base.cg_max, 400);
      o.cg_tol = std::min(base.cg_tol, 1e-2);
      o.extrapolate = false;
      s_->set_options(o);
      s_->set_nodes(s_->model().rest);
      st = s_->step(c);
      ++extra;
      const bool ok = accept(st, o);
      s_->set_options(base);
      if (ok) return finish(st, true, c, extra);
    }
    // Every attempt failed: the last good state stands.
    s_->set_nodes(good_);
    st.status = StepStatus::Diverged;
    st.recoveries = extra;
    st.converged = false;
    return st;
  }

  void reset() override {
    s_->reset();
    s_->nodes(good_);
    std::fill(good_controls_.weights.begin(), good_controls_.weights.end(), 0.0f);
    good_controls_.activations.clear();
    good_controls_.jaw_override = false;
    good_controls_.springs.clear();
    good_controls_.spheres.clear();
  }
  void nodes(std::vector<double>& x) const override { x = good_; }
  void surface(std::vector<double>& s) const override { s_->surface(s); }
  void set_nodes(const std::vector<double>& x) override {
    s_->set_nodes(x);
    good_ = x;
  }
  void forces(const Controls& c, std::vector<double>& f) override { s_->forces(c, f); }
  std::string device() const override { return s_->device(); }
  double time_stiffness_product(int repetitions) override { return s_->time_stiffness_product(repetitions); }
  const SimModel& model() const override { return s_->model(); }
  const SolverOptions& options() const override { return s_->options(); }
  void set_options(const SolverOptions& opt) override { s_->set_options(opt); }

 private:
  // A step is kept when it is not diverged and its positions are finite
  // (read into scratch_, which becomes the good state on success).
  bool accept(const StepStats& st, const SolverOptions& o) {
    if (step_diverged(st, s_->model(), o, rest_inverted_)) return false;
    s_->nodes(scratch_);
    return all_finite(scratch_);
  }
  StepStats finish(StepStats st, bool recovered, const Controls& c, int extra = 0) {
    good_.swap(scratch_);
    good_controls_ = c;
    st.recoveries = extra;
    st.status = recovered ? StepStatus::Recovered : st.converged ? StepStatus::Converged : StepStatus::Unconverged;
    return st;
  }

  std::unique_ptr<Simulator> s_;
  std::vector<double> good_, scratch_;  // last good nodes; the candidate being checked
  Controls good_controls_;
  int rest_inverted_ = 0;
};

}  // namespace

std::unique_ptr<Simulator> make_recovering_simulator(std::unique_ptr<Simulator> inner) {
  return std::make_unique<RecoveringSimulator>(std::move(inner));
}

}  // namespace facesr
