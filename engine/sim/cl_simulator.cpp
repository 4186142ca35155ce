#include "sim/cl_simulator.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <map>

#include "compute/cl_buffer.h"
#include "compute/cl_context.h"
#include "compute/cl_program.h"
#include "core/error.h"
#include "core/progress.h"
#include "sim/recovering_simulator.h"
#include "sim/stiffness_pattern.h"

namespace facesr {

namespace {

using compute::Buffer;
using compute::LocalMemory;

template <typename Real>
std::vector<Real> to_real(const std::vector<double>& v) {
  return std::vector<Real>(v.begin(), v.end());
}

template <typename Real>
class ClSimulator final : public Simulator {
 public:
  ClSimulator(const SimModel& m, const SolverOptions& opt, const compute::DeviceInfo& dev,
              ClSimulatorOptions::Elements elements, ClSimulatorOptions::Product product, int cg_batch)
      : m_(m), opt_(opt), ctx_(dev), cg_batch_(cg_batch) {
    assembled_ = product == ClSimulatorOptions::Product::Assembled;
    using Elements = ClSimulatorOptions::Elements;
    simd_elements_ = elements == Elements::Simd || (elements == Elements::Auto && dev.type == compute::DeviceType::Cpu);
    std::string options = "-cl-std=CL1.2";
    if (sizeof(Real) == 4) options += " -DFSR_REAL_FLOAT -cl-single-precision-constant";
    prog_ = ctx_.build_program({"fsr_material.h", "sim.cl"}, options);
    const cl_mem_flags ro = CL_MEM_READ_ONLY;
    const size_t N = m.num_nodes, T = m.num_tets, S = m.num_surface;
    const auto& mp = m.material;
    mat_ = Buffer<Real>(ctx_, std::vector<Real>{Real(mp.mu10), Real(mp.mu01), Real(mp.kappa), Real(mp.j_min),
                                                Real(mp.sigma_max), Real(mp.p1), Real(mp.p2), Real(mp.stretch_lin)},
                        ro);
    rest_ = Buffer<Real>(ctx_, to_real<Real>(m.rest), ro);
    tets_ = Buffer<cl_int>(ctx_, m.tets, ro);
    Dminv_ = Buffer<Real>(ctx_, to_real<Real>(m.Dminv), ro);
    vol_ = Buffer<Real>(ctx_, to_real<Real>(m.volume), ro);
    fibre_ = Buffer<Real>(ctx_, to_real<Real>(m.fibre), ro);
    muscle_ = Buffer<cl_int>(ctx_, m.muscle, ro);
    bone_ = Buffer<cl_uchar>(ctx_, m.node_bone, ro);
    surf_nodes_ = Buffer<cl_int>(ctx_, m.surf_nodes, ro);
    surf_w_ = Buffer<Real>(ctx_, to_real<Real>(m.surf_weights), ro);
    surf_rest_ = Buffer<Real>(ctx_, to_real<Real>(m.surf_rest), ro);
    track_k_ = Buffer<Real>(ctx_, to_real<Real>(m.track_k), ro);
    deltas_ = Buffer<float>(ctx_, m.shape_deltas, ro);
    for (int which = 0; which < 2; ++which) {
      const SimModel::Incidence& inc = which ? m.inc_tracked : m.inc_all;
      inc_[which].count = uint32_t(inc.vertices.size());
      inc_[which].vertices = Buffer<cl_int>(ctx_, inc.vertices, ro);
      inc_[which].offset = Buffer<cl_int>(ctx_, inc.offset, ro);
      inc_[which].slot = Buffer<cl_int>(ctx_, inc.slot, ro);
    }

    build_track_matrix();
    weights_ = Buffer<float>(ctx_, std::max<size_t>(1, m.num_shapes));
    act_ = Buffer<Real>(ctx_, std::max<size_t>(1, m.num_muscles));
    target_ = Buffer<Real>(ctx_, 3 * S);
    spring_k_ = Buffer<Real>(ctx_, S);
    spring_target_ = Buffer<Real>(ctx_, 3 * S);
    for (auto* b : {&x_, &x_prev_, &xt_, &g_, &d_, &r_, &z_, &p_, &q_, &s_}) *b = Buffer<Real>(ctx_, 3 * N);
    slots_ = Buffer<Real>(ctx_, 12 * (T + S));
    dslots_ = Buffer<Real>(ctx_, 36 * (T + S));
    // Component-major copies for product_tets (cl/sim.cl): x[k·Tp + t],
    // padded to whole vectors with zero Dminv and volume.
    // The per-tet scalars phi and alpha are padded the same way (the one-tet
    // kernels read only their first T entries).
    Tp_ = uint32_t((T + kProductLanes - 1) / kProductLanes * kProductLanes);
    {
      std::vector<cl_int> tets_cm(4 * size_t(Tp_), 0);
      std::vector<Real> Dminv_cm(9 * size_t(Tp_), Real(0)), fibre_cm(3 * size_t(Tp_), Real(0)),
          vol_p(Tp_, Real(0)), phi_p(Tp_, Real(0));
      for (size_t t = 0; t < T; ++t) {
        for (int k = 0; k < 4; ++k) tets_cm[k * size_t(Tp_) + t] = m.tets[4 * t + k];
        for (int k = 0; k < 9; ++k) Dminv_cm[k * size_t(Tp_) + t] = Real(m.Dminv[9 * t + k]);
        for (int k = 0; k < 3; ++k) fibre_cm[k * size_t(Tp_) + t] = Real(m.fibre[3 * t + k]);
        vol_p[t] = Real(m.volume[t]);
        phi_p[t] = Real(m.phi[t]);
      }
      tets_cm_ = Buffer<cl_int>(ctx_, tets_cm, ro);
      Dminv_cm_ = Buffer<Real>(ctx_, Dminv_cm, ro);
      fibre_cm_ = Buffer<Real>(ctx_, fibre_cm, ro);
      vol_p_ = Buffer<Real>(ctx_, vol_p, ro);
      phi_ = Buffer<Real>(ctx_, phi_p, ro);
      alpha_ = Buffer<Real>(ctx_, std::vector<Real>(Tp_, Real(0)));
      C_ = Buffer<float>(ctx_, std::vector<float>(45 * size_t(Tp_), 0.0f));  // packed dP/dF, see tet_hessian
    }
    if (assembled_)
      build_stiffness_pattern();
    else
      Ke_ = Buffer<float>(ctx_, 1);  // an unused kernel argument
    surfH_ = Buffer<Real>(ctx_, 9 * std::max<size_t>(1, S));
    Minv_ = Buffer<Real>(ctx_, 9 * N);
    elem_ = Buffer<Real>(ctx_, std::max<size_t>(Tp_, S));
    surf_out_ = Buffer<float>(ctx_, 3 * std::max<size_t>(1, S));
    local_ = 64;
    groups_ = 64;
    node_groups_ = (N + local_ - 1) / local_;
    partial_ = Buffer<Real>(ctx_, 2 * std::max(groups_, node_groups_));
    for (int b = 0; b < 2; ++b) {
      partial2_[b] = Buffer<Real>(ctx_, 2 * node_groups_);
      cg_[b] = Buffer<Real>(ctx_, 5);
    }
    cg_flags_ = Buffer<cl_int>(ctx_, 2);
    no_stop_ = Buffer<cl_int>(ctx_, std::vector<cl_int>{0}, CL_MEM_READ_ONLY);
    for (const char* k : {"frame_tet_alpha", "frame_targets", "frame_targets8", "apply_dirichlet", "tet_energy", "tet_gradient",
                          "tet_hessian", "tet_energy8", "tet_gradient8", "tet_hessian8", "surface_terms", "gather_nodes",
                          "gather_diag_inverse", "precondition", "dot2_partial", "sum_partial",
                          "axpy_to", "scale_to", "extrapolate", "product_tets", "product_surface", "gather_dot", "cg_iteration", "tet_inverted", "embed_surface",
                          "assemble_stiffness", "spmv_dot"})
      kernels_.emplace(k, prog_.kernel(k));
    reset();
  }

  std::string device() const override {
    return ctx_.device().device_name + " (OpenCL, " + (sizeof(Real) == 8 ? "double" : "float") + ")";
  }
  const SimModel& model() const override { return m_; }
  const SolverOptions& options() const override { return opt_; }
  void set_options(const SolverOptions& opt) override { opt_ = opt; }

  void reset() override {
    x_.upload(to_real<Real>(m_.rest));
    have_frame_ = false;
    solved_frames_ = 0;
  }
  void nodes(std::vector<double>& x) const override {
    const auto v = x_.download();
    x.assign(v.begin(), v.end());
  }
  void set_nodes(const std::vector<double>& x) override {
    require(x.size() == 3 * size_t(m_.num_nodes), "set_nodes: expected " + std::to_string(3 * m_.num_nodes) +
                                                       " values, got " + std::to_string(x.size()));
    x_.upload(to_real<Real>(x));
    solved_frames_ = 0;
  }
  void forces(const Controls& c, std::vector<double>& f) override {
    upload_frame(c, prepare_frame(m_, c));
    gradient(x_, g_);
    const auto v = g_.download();
    f.resize(v.size());
    for (size_t i = 0; i < v.size(); ++i) f[i] = -double(v[i]);
  }
  void surface(std::vector<double>& s) const override {
    const uint32_t S = m_.num_surface;
    k("embed_surface").args(S, surf_nodes_, surf_w_, x_, surf_out_).run_1d(S, local_);
    std::vector<float> out(3 * size_t(S));
    surf_out_.download(out.data(), out.size());
    s.assign(out.begin(), out.end());
  }

  StepStats step(const Controls& c) override {
    const auto t0 = std::chrono::steady_clock::now();
    const FrameInputs in = prepare_frame(m_, c);  // validates before touching any state
    last_mark_ = t0;
    upload_frame(c, in);
    mark("upload");
    StepStats st;
    const uint32_t n = 3 * m_.num_nodes;

    // Reference residual: the gradient at the rest mesh with this frame's bone motion.
    apply_dirichlet(rest_, xt_);
    gradient(xt_, g_);
    const double mu = m_.material.shear_modulus();
    const double ref = std::max(std::sqrt(dot(g_, g_)), 1e-3 * mu * m_.mean_edge * m_.mean_edge);
    mark("reference residual");

    if (opt_.extrapolate && solved_frames_ >= 2) {
      k("extrapolate").args(n, x_, x_prev_).run_1d(n, local_);
    } else {
      k("scale_to").args(n, Real(1), x_, x_prev_).run_1d(n, local_);
    }
    apply_dirichlet(x_, x_);
    double e_cur = std::numeric_limits<double>::quiet_NaN();  // energy at x_, once known
    for (int it = 0;; ++it) {
      gradient(x_, g_);
      const double gg = dot(g_, g_);
      mark("gradient");
      st.rel_residual = std::sqrt(gg) / ref;
      st.residuals.push_back(st.rel_residual);
      if (!std::isfinite(st.rel_residual)) {  // the recovering wrapper restarts the frame
        st.finite = false;
        break;
      }
      if (st.rel_residual <= opt_.newton_tol) {
        st.converged = true;
        break;
      }
      if (it >= opt_.newton_max) break;
      // Exact Hessian near equilibrium, definiteness fix on negative curvature
      // (see SolverOptions::exact_hessian_below).
      const bool exact = st.rel_residual < opt_.exact_hessian_below;
      hessian(x_, !exact);
      mark("hessian");
      bool negative = false;
      st.cg_iters += pcg(negative);
      if (exact && negative) {
        hessian(x_, true);
        st.cg_iters += pcg(negative);
      }
      mark("cg");
      ++st.newton_iters;
      const double e0 = std::isnan(e_cur) ? energy(x_) : e_cur;
      const double slope = dot(g_, d_);
      double a = 1;
      bool accepted = false;
      for (int ls = 0; ls <= opt_.line_search_max; ++ls) {
        k("axpy_to").args(n, Real(a), x_, d_, xt_).run_1d(n, local_);
        const double e = energy(xt_);
        if (std::isfinite(e) && e <= e0 + 1e-4 * a * slope + 1e-13 * std::abs(e0)) {  // roundoff slack
          accepted = true;
          e_cur = e;
          break;
        }
        a *= 0.5;
        ++st.line_search_halvings;
      }
      mark("line search");
      if (!accepted) break;
      std::swap(x_, xt_);
    }
    st.energy = std::isnan(e_cur) ? energy(x_) : e_cur;
    st.status = st.converged ? StepStatus::Converged : StepStatus::Unconverged;
    ++solved_frames_;
    const uint32_t T = m_.num_tets;
    k("tet_inverted").args(T, tets_, x_, Dminv_, elem_).run_1d(T, local_);
    st.inverted_tets = int(std::lround(sum(elem_, T)));
    mark("finish");
    st.ms = 1e3 * seconds_since(t0);
    return st;
  }

  ~ClSimulator() override {
    if (!profile_) return;
    for (const auto& [phase, ms] : phase_ms_) std::fprintf(stderr, "[sim profile] %-20s %9.1f ms\n", phase.c_str(), ms);
  }

  double time_stiffness_product(int reps) override {
    if (!have_frame_) {
      Controls c;
      c.weights.assign(m_.num_shapes, 0.0f);
      upload_frame(c, prepare_frame(m_, c));
    }
    const uint32_t n = 3 * m_.num_nodes;
    k("scale_to").args(n, Real(1), x_, p_).run_1d(n, local_);  // any non-trivial vector will do
    hessian(x_);
    product_dot(p_, q_);  // untimed: the first launch of a kernel includes PoCL's compile for it
    ctx_.finish();
    const auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < reps; ++i) product_dot(p_, q_);  // product, gather and p·q: one CG iteration's K·p
    ctx_.finish();
    const double ms = 1e3 * seconds_since(t0) / reps;
    if (profile_) profile_kernels(reps);
    return ms;
  }

  // FACESR_SIM_PROFILE=1: the mean time of each per-frame kernel, alone
  // (the gradient's, the Hessian's, the line search's, one CG iteration's).
  void profile_kernels(int reps) {
    const uint32_t T = m_.num_tets, S = cur_->count, N = m_.num_nodes;
    const auto time = [&](const char* name, const std::function<void()>& f) {
      ctx_.finish();
      const auto t0 = std::chrono::steady_clock::now();
      for (int i = 0; i < reps; ++i) f();
      ctx_.finish();
      std::fprintf(stderr, "[sim profile] kernel %-18s %8.1f us\n", name, 1e6 * seconds_since(t0) / reps);
    };
    time("tet_gradient8", [&] {
      k("tet_gradient8").args(T, Tp_, mat_, tets_cm_, x_, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, slots_).run_1d(Tp_ / kProductLanes, 8);
    });
    for (const cl_int assemble : {0, 1}) {
      if (assemble && !assembled_) continue;
      time(assemble ? "tet_hessian8 (blocks)" : "tet_hessian8", [&] {
        k("tet_hessian8")
            .args(T, Tp_, mat_, tets_cm_, x_, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, cl_int(1), C_, dslots_,
                  assemble, Ke_)
            .run_1d(Tp_ / kProductLanes, 8);
      });
    }
    if (assembled_) {
      time("assemble_stiffness", [&] { assemble_matrix(true); });
      time("spmv_dot", [&] {
        k("spmv_dot").args(N, kp_row_, kp_col_, K_, p_, q_, partial_, LocalMemory{local_ * sizeof(Real)}, no_stop_).run_1d(N, local_);
      });
    }
    time("tet_energy8", [&] {
      k("tet_energy8").args(T, Tp_, mat_, tets_cm_, x_, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, elem_).run_1d(Tp_ / kProductLanes, 8);
    });
    time("surface_terms(1)", [&] { surface_terms(x_, 1); });
    time("surface_terms(2)", [&] { surface_terms(x_, 2); });
    time("gather_nodes", [&] { k("gather_nodes").args(N, cur_->offset, cur_->slot, bone_, slots_, g_).run_1d(N, local_); });
    time("gather_diag_inv", [&] {
      k("gather_diag_inverse").args(N, cur_->offset, cur_->slot, bone_, dslots_, Minv_).run_1d(N, local_);
    });
    time("sum (energy)", [&] { sum(elem_, T); });
    time("product_tets", [&] { k("product_tets").args(T, Tp_, tets_cm_, p_, Dminv_cm_, vol_p_, C_, slots_, no_stop_).run_1d(Tp_ / kProductLanes, 8); });
    time("product_surface", [&] { if (S > 0) k("product_surface").args(T, S, p_, cur_->vertices, surf_nodes_, surf_w_, surfH_, slots_, no_stop_).run_1d(S, local_); });
    time("gather_dot (track)", [&] {
      k("gather_dot")
          .args(N, track_inc_offset_, track_inc_slot_, L_offset_, L_col_, L_val_, bone_, slots_, q_, p_, partial_,
                LocalMemory{local_ * sizeof(Real)}, no_stop_)
          .run_1d(N, local_);
    });
    time("gather_dot (slots)", [&] {
      k("gather_dot")
          .args(N, cur_->offset, cur_->slot, L_none_offset_, L_col_, L_val_, bone_, slots_, q_, p_, partial_,
                LocalMemory{local_ * sizeof(Real)}, no_stop_)
          .run_1d(N, local_);
    });
    time("partials read", [&] { sum_partials(1); });
    // A first iteration (γ = δ = 1: α = 1, β = 0.5) that never stops: the
    // iteration's full work each time.
    cg_[0].upload(std::vector<Real>{Real(1), Real(0), Real(0.5), Real(1), Real(0)}.data(), 5);
    const cl_int running[2] = {0, 0}, stopped[2] = {1, 0};
    cg_flags_.upload(running, 2);
    time("cg_iteration", [&] { enqueue_cg_iteration(0, cg_flags_); });
    time("queued iteration", [&] {
      enqueue_cg_iteration(0, cg_flags_);
      enqueue_product_dot(z_, q_, cg_flags_);
    });
    time("whole iteration", [&] {
      enqueue_cg_iteration(0, cg_flags_);
      enqueue_product_dot(z_, q_, cg_flags_);
      sum_partials(1);
    });
    // An iteration as pcg queues it (no read-back), stopped at once: the launches alone.
    cg_flags_.upload(stopped, 2);
    time("stopped iteration", [&] {
      enqueue_cg_iteration(1, cg_flags_);
      enqueue_product_dot(z_, q_, cg_flags_);
    });
  }

 private:
  compute::Kernel& k(const char* name) const { return kernels_.at(name); }

  // FACESR_SIM_PROFILE=1: per-phase wall times (with a queue drain after each
  // phase, so they add up to slightly more than an unprofiled step), printed
  // when the simulator is destroyed.
  void mark(const char* phase) {
    if (!profile_) return;
    ctx_.finish();
    const auto now = std::chrono::steady_clock::now();
    phase_ms_[phase] += 1e3 * std::chrono::duration<double>(now - last_mark_).count();
    last_mark_ = now;
  }

  void upload_frame(const Controls& c, const FrameInputs& in) {
    if (m_.num_shapes > 0) weights_.upload(c.weights);
    if (m_.num_muscles > 0) act_.upload(to_real<Real>(in.muscle_activation));
    std::vector<double> frame(12);
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) frame[3 * i + j] = in.jaw_R(i, j);
      frame[9 + i] = in.jaw_t[i];
    }
    for (const auto& s : in.spheres)
      frame.insert(frame.end(), {s.centre.x(), s.centre.y(), s.centre.z(), s.radius, s.stiffness});
    if (frame_.size() < frame.size()) frame_ = Buffer<Real>(ctx_, frame.size());
    frame_.upload(to_real<Real>(frame));
    nspheres_ = uint32_t(in.spheres.size());
    // Only the tracked vertices carry forces unless springs or spheres may touch any vertex.
    bool springs = false;
    for (double kv : in.spring_k) springs = springs || kv > 0;
    cur_ = (springs || nspheres_ > 0) ? &inc_[0] : &inc_[1];
    have_frame_ = true;
    // Spring arrays are per surface vertex (0.3 MB on ICT): a frame without
    // springs after one without springs leaves the device's zeros in place.
    if (springs || springs_on_device_) {
      spring_k_.upload(to_real<Real>(in.spring_k));
      spring_target_.upload(to_real<Real>(in.spring_target));
      springs_on_device_ = springs;
    }
    const uint32_t T = m_.num_tets, S = m_.num_surface, B = m_.num_shapes;
    k("frame_tet_alpha").args(T, muscle_, act_, alpha_).run_1d(T, local_);
    if (simd_elements_)
      k("frame_targets8").args(S, B, surf_rest_, deltas_, weights_, target_).run_1d((3 * size_t(S) + 7) / 8, 8);
    else
      k("frame_targets").args(S, B, surf_rest_, deltas_, weights_, target_).run_1d(3 * size_t(S), local_);
  }

  void apply_dirichlet(const Buffer<Real>& from, Buffer<Real>& to) {
    const uint32_t N = m_.num_nodes;
    if (&from != &to) k("scale_to").args(3 * N, Real(1), from, to).run_1d(3 * size_t(N), local_);
    k("apply_dirichlet").args(N, rest_, bone_, frame_, to).run_1d(N, local_);
  }

  void surface_terms(const Buffer<Real>& x, int mode) {
    const uint32_t S = cur_->count, T = m_.num_tets;
    k("surface_terms")
        .args(S, T, cl_int(mode), cur_->vertices, surf_nodes_, surf_w_, x, track_k_, target_, spring_k_, spring_target_, frame_,
              nspheres_, elem_, slots_, surfH_, dslots_)
        .run_1d(S, local_);
  }

  void gradient(const Buffer<Real>& x, Buffer<Real>& g) {
    const uint32_t T = m_.num_tets, N = m_.num_nodes;
    if (simd_elements_)
      k("tet_gradient8").args(T, Tp_, mat_, tets_cm_, x, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, slots_).run_1d(Tp_ / kProductLanes, 8);
    else
      k("tet_gradient").args(T, mat_, tets_, x, Dminv_, vol_, fibre_, phi_, alpha_, slots_).run_1d(T, local_);
    surface_terms(x, 1);
    k("gather_nodes").args(N, cur_->offset, cur_->slot, bone_, slots_, g).run_1d(N, local_);
  }

  double energy(const Buffer<Real>& x) {
    const uint32_t T = m_.num_tets, S = cur_->count;
    if (simd_elements_)
      k("tet_energy8").args(T, Tp_, mat_, tets_cm_, x, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, elem_).run_1d(Tp_ / kProductLanes, 8);
    else
      k("tet_energy").args(T, mat_, tets_, x, Dminv_, vol_, fibre_, phi_, alpha_, elem_).run_1d(T, local_);
    const double e = sum(elem_, T);
    surface_terms(x, 0);
    return e + sum(elem_, S);
  }

  void hessian(const Buffer<Real>& x, bool fix = true) {
    const uint32_t T = m_.num_tets, N = m_.num_nodes;
    const cl_int assemble = assembled_ ? 1 : 0;
    if (simd_elements_)
      k("tet_hessian8")
          .args(T, Tp_, mat_, tets_cm_, x, Dminv_cm_, vol_p_, fibre_cm_, phi_, alpha_, cl_int(fix ? 1 : 0), C_, dslots_,
                assemble, Ke_)
          .run_1d(Tp_ / kProductLanes, 8);
    else
      k("tet_hessian")
          .args(T, mat_, tets_, x, Dminv_, vol_, fibre_, phi_, alpha_, cl_int(fix ? 1 : 0), Tp_, C_, dslots_, assemble,
                Ke_)
          .run_1d(T, local_);
    if (assembled_) {
      // Track springs only: their fixed share is in the pattern, no surface pass.
      const bool track = cur_ == &inc_[1];
      if (!track) surface_terms(x, fix ? 2 : 3);
      assemble_matrix(track);
      return;
    }
    surface_terms(x, fix ? 2 : 3);
    k("gather_diag_inverse").args(N, cur_->offset, cur_->slot, bone_, dslots_, Minv_).run_1d(N, local_);
  }


  // K and the block-Jacobi inverse from the tets' blocks in Ke_ and, unless
  // `track` (the track springs' fixed share only), the surface Hessians.
  void assemble_matrix(bool track) {
    k("assemble_stiffness")
        .args(uint32_t(m_.num_nodes), cl_int(track ? 1 : 0), kp_row_, kp_col_, kp_tet_offset_, kp_tet_ref_,
              kp_surf_offset_, kp_surf_ref_, kp_track_, inc_[0].vertices, surf_w_, surfH_, Ke_, K_, Minv_)
        .run_1d(m_.num_nodes, local_);
  }

  // q = K p over free nodes; returns p·q.
  double product_dot(const Buffer<Real>& p, Buffer<Real>& q) {
    enqueue_product_dot(p, q, no_stop_);
    return sum_partials(1).first;
  }

  // CG iteration i (0-based) of a solve: its scalars and vector update
  // (cg_iteration in cl/sim.cl), reading the scalars and r·r, r·u partial
  // sums of iteration i − 1 from buffer i % 2 and writing its own to the
  // other; nothing is done once flags[0] ≠ 0.
  void enqueue_cg_iteration(int i, const Buffer<cl_int>& flags) {
    const int a = i % 2, b = 1 - a;
    k("cg_iteration")
        .args(uint32_t(m_.num_nodes), cl_uint(node_groups_), cl_int(i == 0 ? 1 : 0), partial_, partial2_[a], cg_[a],
              cg_[b], flags, z_, q_, p_, s_, d_, r_, Minv_, partial2_[b], LocalMemory{local_ * sizeof(Real)},
              LocalMemory{local_ * sizeof(Real)})
        .run_1d(m_.num_nodes, local_);
  }

  // Nothing is done while stop[0] ≠ 0 (see pcg).
  void enqueue_product_dot(const Buffer<Real>& p, Buffer<Real>& q, const Buffer<cl_int>& stop) {
    const uint32_t T = m_.num_tets, S = cur_->count, N = m_.num_nodes;
    if (assembled_) {
      k("spmv_dot")
          .args(N, kp_row_, kp_col_, K_, p, q, partial_, LocalMemory{local_ * sizeof(Real)}, stop)
          .run_1d(N, local_);
      return;
    }
    k("product_tets").args(T, Tp_, tets_cm_, p, Dminv_cm_, vol_p_, C_, slots_, stop).run_1d(Tp_ / kProductLanes, 8);
    if (cur_ == &inc_[1]) {  // track springs only: see gather_dot
      k("gather_dot")
          .args(N, track_inc_offset_, track_inc_slot_, L_offset_, L_col_, L_val_, bone_, slots_, q, p, partial_,
                LocalMemory{local_ * sizeof(Real)}, stop)
          .run_1d(N, local_);
      return;
    }
    if (S > 0)
      k("product_surface").args(T, S, p, cur_->vertices, surf_nodes_, surf_w_, surfH_, slots_, stop).run_1d(S, local_);
    k("gather_dot")
        .args(N, cur_->offset, cur_->slot, L_none_offset_, L_col_, L_val_, bone_, slots_, q, p, partial_,
              LocalMemory{local_ * sizeof(Real)}, stop)
        .run_1d(N, local_);
  }

  // The track springs' node matrix L = Σ_v k_v w_v w_vᵀ (CSR; see
  // gather_dot in cl/sim.cl) and the tets-only incidence it goes with.
  void build_track_matrix() {
    const size_t N = m_.num_nodes, T = m_.num_tets;
    std::vector<std::map<int32_t, double>> rows(N);
    for (int v = 0; v < m_.num_surface; ++v) {
      const double kt = m_.track_k[v];
      if (!(kt > 0)) continue;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b)
          rows[m_.surf_nodes[4 * v + a]][m_.surf_nodes[4 * v + b]] +=
              kt * m_.surf_weights[4 * v + a] * m_.surf_weights[4 * v + b];
    }
    std::vector<cl_int> offset(N + 1, 0), col, inc_offset(N + 1, 0), inc_slot;
    std::vector<Real> val;
    const SimModel::Incidence& inc = m_.inc_tracked;
    for (size_t v = 0; v < N; ++v) {
      for (const auto& [u, l] : rows[v]) {
        col.push_back(u);
        val.push_back(Real(l));
      }
      offset[v + 1] = cl_int(col.size());
      for (int i = inc.offset[v]; i < inc.offset[v + 1]; ++i)
        if (size_t(inc.slot[i]) < 4 * T) inc_slot.push_back(inc.slot[i]);
      inc_offset[v + 1] = cl_int(inc_slot.size());
    }
    const cl_mem_flags ro = CL_MEM_READ_ONLY;
    // OpenCL buffers cannot be empty: pad with an unused entry.
    if (col.empty()) col.push_back(0), val.push_back(Real(0));
    if (inc_slot.empty()) inc_slot.push_back(0);
    L_offset_ = Buffer<cl_int>(ctx_, offset, ro);
    L_none_offset_ = Buffer<cl_int>(ctx_, std::vector<cl_int>(N + 1, 0), ro);
    L_col_ = Buffer<cl_int>(ctx_, col, ro);
    L_val_ = Buffer<Real>(ctx_, val, ro);
    track_inc_offset_ = Buffer<cl_int>(ctx_, inc_offset, ro);
    track_inc_slot_ = Buffer<cl_int>(ctx_, inc_slot, ro);
  }

  // The assembled stiffness matrix's pattern and sources (see assemble_stiffness).
  void build_stiffness_pattern() {
    const StiffnessPattern sp = make_stiffness_pattern(m_);
    const cl_mem_flags ro = CL_MEM_READ_ONLY;
    // OpenCL buffers cannot be empty: pad with an unused entry.
    const auto padded = [](std::vector<int32_t> v) {
      if (v.empty()) v.push_back(0);
      return v;
    };
    kp_row_ = Buffer<cl_int>(ctx_, sp.row_offset, ro);
    kp_col_ = Buffer<cl_int>(ctx_, padded(sp.col), ro);
    kp_tet_offset_ = Buffer<cl_int>(ctx_, sp.tet_offset, ro);
    // Refs resolved to offsets into Ke (KE_INDEX in cl/sim.cl) once, here.
    std::vector<int32_t> ke_ref(sp.tet_ref.size());
    for (size_t i = 0; i < ke_ref.size(); ++i) {
      const int64_t ref = sp.tet_ref[i], q = ref >> 1, t = q / 10, pair = q % 10;
      const int64_t L = kProductLanes, at = ((t / L) * 90 + 9 * pair) * L + t % L;  // KE_INDEX
      if (2 * at + 1 > std::numeric_limits<int32_t>::max()) throw Error("stiffness pattern: too many tets for 32-bit offsets");
      ke_ref[i] = int32_t(2 * at + (ref & 1));
    }
    kp_tet_ref_ = Buffer<cl_int>(ctx_, padded(ke_ref), ro);
    kp_surf_offset_ = Buffer<cl_int>(ctx_, sp.surf_offset, ro);
    kp_surf_ref_ = Buffer<cl_int>(ctx_, padded(sp.surf_ref), ro);
    std::vector<Real> track = to_real<Real>(sp.track);
    if (track.empty()) track.push_back(Real(0));
    kp_track_ = Buffer<Real>(ctx_, track, ro);
    K_ = Buffer<float>(ctx_, std::max<size_t>(1, 9 * sp.num_blocks()));
    Ke_ = Buffer<float>(ctx_, 90 * size_t(Tp_));
  }

  // Host sum of the per-group partials of a node kernel (1 or 2 interleaved sums).
  std::pair<double, double> sum_partials(int count) { return sum_partials(count, partial_); }
  std::pair<double, double> sum_partials(int count, const Buffer<Real>& partial) {
    std::vector<Real> part(count * node_groups_);
    partial.download(part.data(), part.size());
    double s1 = 0, s2 = 0;
    for (size_t i = 0; i < node_groups_; ++i) {
      s1 += part[count * i];
      if (count == 2) s2 += part[2 * i + 1];
    }
    return {s1, s2};
  }

  std::pair<double, double> dot2(const Buffer<Real>& a, const Buffer<Real>& b, const Buffer<Real>& c,
                                 const Buffer<Real>& d) {
    const uint32_t n = 3 * m_.num_nodes;
    k("dot2_partial")
        .args(n, a, b, c, d, partial_, LocalMemory{local_ * sizeof(Real)}, LocalMemory{local_ * sizeof(Real)})
        .run_1d(local_ * groups_, local_);
    std::vector<Real> part(2 * groups_);
    partial_.download(part.data(), part.size());
    double s1 = 0, s2 = 0;
    for (size_t i = 0; i < groups_; ++i) s1 += part[2 * i], s2 += part[2 * i + 1];
    return {s1, s2};
  }
  double dot(const Buffer<Real>& a, const Buffer<Real>& b) { return dot2(a, b, a, b).first; }

  double sum(const Buffer<Real>& a, uint32_t n) {
    k("sum_partial").args(n, a, partial_, LocalMemory{local_ * sizeof(Real)}).run_1d(local_ * groups_, local_);
    std::vector<Real> part(groups_);
    partial_.download(part.data(), part.size());
    double s = 0;
    for (Real v : part) s += v;
    return s;
  }

  // K d = −g on the free nodes (bone rows are zero in g, q and Minv), by
  // preconditioned CG in the single-reduction form of Chronopoulos and Gear
  // (1989): the same iterates as textbook PCG in exact arithmetic, but each
  // iteration's three scalars (r·r, r·u and u·Ku, u = M⁻¹r) come from one
  // reduction after its one product. The scalar recurrences run on the
  // device too (cg_iteration), so the host enqueues iterations in batches and
  // reads the stopping flags once per batch instead of waiting on the
  // device every iteration (on CPU devices that wait rivalled the product);
  // iterations queued after the stop do nothing. The price is one extra
  // product per solve (K u0 before the first step).
  int pcg(bool& negative) {
    negative = false;
    const uint32_t n = 3 * m_.num_nodes, N = m_.num_nodes;
    k("scale_to").args(n, Real(-1), g_, r_).run_1d(n, local_);
    k("scale_to").args(n, Real(0), g_, d_).run_1d(n, local_);
    k("scale_to").args(n, Real(0), g_, p_).run_1d(n, local_);
    k("scale_to").args(n, Real(0), g_, s_).run_1d(n, local_);
    k("precondition").args(N, Minv_, r_, z_).run_1d(N, local_);  // z_ holds u
    auto [rr, gamma] = dot2(r_, r_, r_, z_);
    const double bnorm = std::sqrt(rr);
    if (bnorm == 0) return 0;
    const double delta = product_dot(z_, q_);  // q_ holds w = K u
    const std::vector<Real> cg0 = {Real(gamma), Real(0), Real(0), Real(delta), Real(opt_.cg_tol * bnorm)};
    cg_[0].upload(cg0.data(), cg0.size());
    const cl_int running[2] = {0, 0};
    cg_flags_.upload(running, 2);
    // The first batch covers most solves (the last solve's count), the
    // later ones are short so that few iterations are queued past the stop.
    int queued = 0, batch = cg_batch_ > 0 ? cg_batch_ : std::max(4, last_cg_iters_);
    cl_int flags[2] = {0, 0};
    while (queued < opt_.cg_max) {
      const int count = std::min(batch, opt_.cg_max - queued);
      for (int i = 0; i < count; ++i) {
        enqueue_cg_iteration(queued + i, cg_flags_);
        enqueue_product_dot(z_, q_, cg_flags_);
      }
      queued += count;
      cg_flags_.download(flags, 2);  // waits for the batch
      if (flags[0] != 0) break;
      batch = cg_batch_ > 0 ? cg_batch_ : 4;
    }
    const int it = flags[1];
    negative = flags[0] == 2;
    last_cg_iters_ = it;
    if (it == 0) k("scale_to").args(n, Real(1), z_, d_).run_1d(n, local_);
    return it;
  }

  SimModel m_;
  SolverOptions opt_;
  compute::Context ctx_;
  compute::Program prog_;
  mutable std::map<std::string, compute::Kernel> kernels_;
  Buffer<Real> mat_, rest_, Dminv_, vol_, fibre_, phi_, surf_w_, surf_rest_, track_k_;
  Buffer<cl_int> tets_, muscle_, surf_nodes_;
  struct IncidenceBuffers {
    uint32_t count = 0;
    Buffer<cl_int> vertices, offset, slot;
  };
  IncidenceBuffers inc_[2];  // every surface vertex, tracked vertices only
  IncidenceBuffers* cur_ = &inc_[0];
  Buffer<cl_uchar> bone_;
  Buffer<float> deltas_, weights_;
  mutable Buffer<float> surf_out_;
  Buffer<Real> act_, alpha_, target_, spring_k_, spring_target_, frame_;
  // PRODUCT_LANES in cl/sim.cl: tets per 512-bit vector.
  static constexpr uint32_t kProductLanes = sizeof(Real) == 4 ? 16 : 8;
  uint32_t Tp_ = 0;
  Buffer<cl_int> tets_cm_;
  Buffer<Real> Dminv_cm_, fibre_cm_, vol_p_;
  Buffer<cl_int> L_offset_, L_none_offset_, L_col_, track_inc_offset_, track_inc_slot_;
  Buffer<Real> L_val_;
  bool simd_elements_ = false;
  Buffer<Real> x_, x_prev_, xt_, g_, d_, r_, z_, p_, q_, s_, slots_, dslots_, surfH_, Minv_, elem_, partial_;
  Buffer<Real> partial2_[2];  // r·r and r·u partial sums, by iteration parity (see enqueue_cg_iteration)
  Buffer<float> C_;
  // The assembled product (ClSimulatorOptions::Product::Assembled): pattern,
  // per-tet blocks, K.
  bool assembled_ = true;
  Buffer<cl_int> kp_row_, kp_col_, kp_tet_offset_, kp_tet_ref_, kp_surf_offset_, kp_surf_ref_;
  Buffer<Real> kp_track_;
  Buffer<float> K_, Ke_;
  Buffer<Real> cg_[2];           // CG scalars by iteration parity, see cg_iteration in cl/sim.cl
  Buffer<cl_int> cg_flags_, no_stop_;
  int last_cg_iters_ = 0;  // the last solve's CG iterations: the next one's first batch
  int cg_batch_ = 0;       // ClSimulatorOptions::cg_batch
  uint32_t nspheres_ = 0;
  size_t local_ = 64, groups_ = 64, node_groups_ = 1;
  bool have_frame_ = false;
  bool springs_on_device_ = true;  // until the first upload the buffers hold garbage
  int solved_frames_ = 0;
  bool profile_ = std::getenv("FACESR_SIM_PROFILE") != nullptr;
  std::map<std::string, double> phase_ms_;
  std::chrono::steady_clock::time_point last_mark_;
};

}  // namespace

std::unique_ptr<Simulator> make_cl_simulator(const SimModel& model, const SolverOptions& opt,
                                             const ClSimulatorOptions& cl) {
  if (cl.cg_batch < 0) throw Error("ClSimulatorOptions::cg_batch must be 0 (automatic) or positive, got " + std::to_string(cl.cg_batch));
  const compute::DeviceInfo dev = compute::select_device(cl.device);
  std::unique_ptr<Simulator> sim;
  if (dev.double_support && !cl.single_precision)
    sim = std::make_unique<ClSimulator<double>>(model, opt, dev, cl.elements, cl.product, cl.cg_batch);
  else
    sim = std::make_unique<ClSimulator<float>>(model, opt, dev, cl.elements, cl.product, cl.cg_batch);
  return opt.recover ? make_recovering_simulator(std::move(sim)) : std::move(sim);
}

}  // namespace facesr
