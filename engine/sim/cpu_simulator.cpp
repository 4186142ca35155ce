// CPU reference simulator: the Newton / PCG / line-search loop of
// SolverOptions on the energy of cpu_forces.h. The OpenCL simulator runs the
// same algorithm with device buffers.
#include <Eigen/Dense>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cmath>
#include <limits>

#include "core/error.h"
#include "core/progress.h"
#include "sim/assembled_stiffness.h"
#include "sim/contact.h"
#include "sim/cpu_forces.h"
#include "sim/recovering_simulator.h"
#include "sim/simulator.h"

namespace facesr {

void embed_surface(const SimModel& m, const std::vector<double>& x, std::vector<double>& s) {
  s.assign(3 * size_t(m.num_surface), 0.0);
  for (int v = 0; v < m.num_surface; ++v)
    for (int k = 0; k < 4; ++k) {
      const int n = m.surf_nodes[4 * v + k];
      const double w = m.surf_weights[4 * v + k];
      for (int c = 0; c < 3; ++c) s[3 * v + c] += w * x[3 * size_t(n) + c];
    }
}

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  double s = 0;
#pragma omp parallel for reduction(+ : s) schedule(static)
  for (long i = 0; i < long(a.size()); ++i) s += a[i] * b[i];
  return s;
}

class CpuSimulator final : public Simulator {
 public:
  CpuSimulator(const SimModel& m, const SolverOptions& opt, std::shared_ptr<ContactSource> contacts, bool resolve)
      : m_(m), opt_(opt), contacts_(std::move(contacts)), resolve_(resolve) {
    reset();
  }

  void reset() override {
    x_ = m_.rest;
    solved_frames_ = 0;
  }
  void nodes(std::vector<double>& x) const override { x = x_; }
  void surface(std::vector<double>& s) const override { embed_surface(m_, x_, s); }
  void set_nodes(const std::vector<double>& x) override {
    require(x.size() == x_.size(), "set_nodes: expected " + std::to_string(x_.size()) + " values, got " +
                                       std::to_string(x.size()));
    x_ = x;
    solved_frames_ = 0;
  }
  void forces(const Controls& c, std::vector<double>& f) override {
    const FrameInputs in = prepare_frame(m_, c);
    energy_gradient(m_, in, tet_activations(m_, in), x_, f);
    if (contacts_ && resolve_) {
      contacts_->detect(x_, in, planes_);
      contact_gradient(planes_, x_, f);
    }
    mask(f);
    for (double& v : f) v = -v;
  }
  std::string device() const override {
    return contacts_ && resolve_ ? "cpu-reference (Eigen, double) + Embree contacts" : "cpu-reference (Eigen, double)";
  }
  const SimModel& model() const override { return m_; }
  const SolverOptions& options() const override { return opt_; }
  void set_options(const SolverOptions& opt) override { opt_ = opt; }

  double time_stiffness_product(int reps) override {
    Controls c;
    c.weights.assign(m_.num_shapes, 0.0f);
    const FrameInputs in = prepare_frame(m_, c);
    ElementHessian H;
    element_hessian(m_, in, tet_activations(m_, in), x_, true, H);
    assemble_stiffness(m_, H, stiffness());
    std::vector<double> p(x_.size(), 1.0), q;
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) stiffness_product(K_, p, q);
    return 1e3 * seconds_since(t0) / reps;
  }

  StepStats step(const Controls& c) override {
    const auto t0 = std::chrono::steady_clock::now();
    const FrameInputs in = prepare_frame(m_, c);
    const std::vector<double> alpha = tet_activations(m_, in);
    StepStats st;
    const size_t n = x_.size();

    std::vector<double> g(n), xr = m_.rest;
    dirichlet_positions(m_, in, xr);
    energy_gradient(m_, in, alpha, xr, g);
    mask(g);
    const double mu = m_.material.shear_modulus();
    const double ref = std::max(std::sqrt(dot(g, g)), 1e-3 * mu * m_.mean_edge * m_.mean_edge);

    if (opt_.extrapolate && solved_frames_ >= 2) {
      for (size_t i = 0; i < n; ++i) {
        const double xi = x_[i];
        x_[i] = 2 * xi - x_prev_[i];
        x_prev_[i] = xi;
      }
    } else {
      x_prev_ = x_;
    }
    dirichlet_positions(m_, in, x_);
    double e_cur = std::numeric_limits<double>::quiet_NaN();  // energy at x_, once known
    ElementHessian& H = H_;  // kept between frames: dP/dF alone is 130 MB on the ICT HR mesh
    std::vector<double> d(n), xt(n);
    const bool resolve = contacts_ && resolve_;
    planes_.clear();
    // Contact planes are re-detected during the first iterations, then frozen
    // so that Newton converges on a fixed energy (re-detecting every iteration
    // turns it into a linearly converging fixed-point iteration). A converged
    // state that still penetrates deeper than the tolerance gets fresh planes
    // and more iterations.
    int detections = 0;
    bool refresh = resolve;
    for (int it = 0;; ++it) {
      if (refresh) {
        // The energy changes with the planes, so the cached line-search energy no longer applies.
        contacts_->detect(x_, in, planes_);
        ++detections;
        e_cur = std::numeric_limits<double>::quiet_NaN();
      }
      refresh = resolve && it + 1 < opt_.contact_refresh_iters;
      energy_gradient(m_, in, alpha, x_, g);
      contact_gradient(planes_, x_, g);
      mask(g);
      st.rel_residual = std::sqrt(dot(g, g)) / ref;
      st.residuals.push_back(st.rel_residual);
      if (debug_contacts_) {
        int kinds[3] = {0, 0, 0};
        double depth[3] = {0, 0, 0};
        for (const auto& c : planes_) {
          const int k = std::min(std::max(c.kind, 0), 2);
          kinds[k] += c.penetration > 0;
          depth[k] = std::max(depth[k], c.penetration);
        }
        std::fprintf(stderr, "  newton %d: residual %.2e, contacts %d/%d/%d, depth %.3f/%.3f/%.3f cm\n", it,
                     st.rel_residual, kinds[0], kinds[1], kinds[2], depth[0], depth[1], depth[2]);
      }
      if (!std::isfinite(st.rel_residual)) {  // the recovering wrapper restarts the frame
        st.finite = false;
        break;
      }
      if (st.rel_residual <= opt_.newton_tol) {
        if (resolve && detections < opt_.contact_detections_max && it < opt_.newton_max) {
          std::vector<ContactPlane> fresh;
          contacts_->detect(x_, in, fresh);
          if (max_penetration(fresh) > opt_.penetration_tol_cm) {
            refresh = true;
            continue;
          }
        }
        st.converged = true;
        break;
      }
      if (it >= opt_.newton_max) break;
      // Close to equilibrium the exact Hessian restores Newton's quadratic
      // convergence that element-wise definiteness fixing gives up; if CG
      // meets negative curvature with it, the step is redone with the fix.
      bool exact = st.rel_residual < opt_.exact_hessian_below;
      element_hessian(m_, in, alpha, x_, !exact, H);
      contact_hessian_diag(planes_, x_, H.diag);
      assemble_stiffness(m_, H, stiffness());
      bool negative = false;
      st.cg_iters += pcg(H, g, d, negative);
      if (exact && negative) {
        element_hessian(m_, in, alpha, x_, true, H);
        contact_hessian_diag(planes_, x_, H.diag);
        assemble_stiffness(m_, H, stiffness());
        st.cg_iters += pcg(H, g, d, negative);
      }
      ++st.newton_iters;
      const double e0 = std::isnan(e_cur) ? energy(in, alpha, x_) : e_cur;
      const double slope = dot(g, d);
      double a = 1;
      bool accepted = false;
      for (int ls = 0; ls <= opt_.line_search_max; ++ls) {
        for (size_t i = 0; i < n; ++i) xt[i] = x_[i] + a * d[i];
        const double e = energy(in, alpha, xt);
        if (std::isfinite(e) && e <= e0 + 1e-4 * a * slope + 1e-13 * std::abs(e0)) {  // roundoff slack
          accepted = true;
          e_cur = e;
          break;
        }
        a *= 0.5;
        ++st.line_search_halvings;
      }
      if (!accepted) break;  // no descent along d: report the residual as is
      x_.swap(xt);
    }
    st.energy = std::isnan(e_cur) ? energy(in, alpha, x_) : e_cur;
    st.status = st.converged ? StepStatus::Converged : StepStatus::Unconverged;
    ++solved_frames_;
    if (contacts_) {
      // Measured on the final positions whether or not contacts were resolved.
      std::vector<ContactPlane> final_planes;
      contacts_->detect(x_, in, final_planes);
      st.contacts = count_penetrating(final_planes);
      st.max_penetration_cm = max_penetration(final_planes);
    }
    st.inverted_tets = count_inverted(m_, x_);
    st.ms = 1e3 * seconds_since(t0);
    return st;
  }

 private:
  double energy(const FrameInputs& in, const std::vector<double>& alpha, const std::vector<double>& x) const {
    return total_energy(m_, in, alpha, x) + contact_energy(planes_, x);
  }
  void mask(std::vector<double>& v) const {
    for (int i = 0; i < m_.num_nodes; ++i)
      if (m_.node_bone[i]) v[3 * i] = v[3 * i + 1] = v[3 * i + 2] = 0;
  }

  // Solves K d = −g on the free nodes with block-Jacobi PCG; returns iterations.
  int pcg(const ElementHessian& H, const std::vector<double>& g, std::vector<double>& d, bool& negative) {
    negative = false;
    const size_t n = g.size();
    std::vector<Eigen::Matrix3d> Minv(m_.num_nodes);
    for (int v = 0; v < m_.num_nodes; ++v) {
      Eigen::Matrix3d D = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(&H.diag[9 * size_t(v)]);
      const double det = D.determinant();
      Minv[v] = (m_.node_bone[v] || !(std::abs(det) > 1e-300)) ? Eigen::Matrix3d::Zero() : Eigen::Matrix3d(D.inverse());
    }
    auto precond = [&](const std::vector<double>& r, std::vector<double>& z) {
      for (int v = 0; v < m_.num_nodes; ++v) {
        const Eigen::Vector3d rv(r[3 * v], r[3 * v + 1], r[3 * v + 2]);
        const Eigen::Vector3d zv = Minv[v] * rv;
        for (int k = 0; k < 3; ++k) z[3 * v + k] = zv[k];
      }
    };
    std::vector<double> r(n), z(n), p(n), q(n);
    for (size_t i = 0; i < n; ++i) r[i] = -g[i], d[i] = 0;
    const double bnorm = std::sqrt(dot(r, r));
    if (bnorm == 0) return 0;
    precond(r, z);
    p = z;
    double rz = dot(r, z);
    int it = 0;
    while (it < opt_.cg_max) {
      stiffness_product(K_, p, q);
      contact_product(planes_, x_, p, q);
      mask(q);
      const double pq = dot(p, q);
      if (!(pq > 0)) {
        negative = true;
        break;
      }
      const double a = rz / pq;
      for (size_t i = 0; i < n; ++i) d[i] += a * p[i], r[i] -= a * q[i];
      ++it;
      if (std::sqrt(dot(r, r)) <= opt_.cg_tol * bnorm) break;
      precond(r, z);
      const double rz1 = dot(r, z);
      const double b = rz1 / rz;
      rz = rz1;
      for (size_t i = 0; i < n; ++i) p[i] = z[i] + b * p[i];
    }
    if (it == 0) d = z;  // fall back to the preconditioned steepest descent direction
    return it;
  }

  // Built on first use: the pattern takes a moment on an HR mesh and
  // simulators that only evaluate forces never need it.
  AssembledStiffness& stiffness() {
    if (K_.pattern.row_offset.empty()) K_ = make_assembled_stiffness(m_);
    return K_;
  }

  SimModel m_;
  AssembledStiffness K_;
  ElementHessian H_;
  SolverOptions opt_;
  std::shared_ptr<ContactSource> contacts_;
  bool resolve_ = true;
  std::vector<ContactPlane> planes_;  // this Newton iteration's contacts
  // FACESR_CONTACT_DEBUG=1: contacts per kind and depth at every Newton iteration.
  bool debug_contacts_ = std::getenv("FACESR_CONTACT_DEBUG") != nullptr;
  std::vector<double> x_, x_prev_;
  int solved_frames_ = 0;
};

}  // namespace

std::unique_ptr<Simulator> make_cpu_simulator(const SimModel& model, const SolverOptions& opt,
                                              std::shared_ptr<ContactSource> contacts, bool resolve_contacts) {
  auto sim = std::make_unique<CpuSimulator>(model, opt, std::move(contacts), resolve_contacts);
  if (!opt.recover) return sim;
  return make_recovering_simulator(std::move(sim));
}

}  // namespace facesr
