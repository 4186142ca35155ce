// CPU reference simulator: global finite-difference checks (with the track,
// point-spring and sphere terms), patch test, rest equilibrium, muscle
// action, volume preservation and robustness to random controls.
#include <gtest/gtest.h>

#include <random>

#include "rig/lattice.h"
#include "sim/cpu_forces.h"
#include "sim/simulator.h"
#include "test_support.h"

using namespace facesr;

namespace {

// A 3x3x3-cell lattice block whose boundary nodes are attached to the "jaw",
// so that a jaw transform moves the whole boundary rigidly.
Rig block_rig() {
  Rig r;
  r.name = "block";
  Lattice L;
  L.cell = 1;
  L.dims = {3, 3, 3};
  std::vector<long> cells, first;
  for (long c = 0; c < 27; ++c) cells.push_back(c);
  r.lr.mesh = lattice_mesh(L, cells, first);
  const long nt = r.lr.mesh.T.rows();
  r.lr.muscle.assign(nt, 0);
  r.lr.muscle_fraction.assign(nt, 1.0f);
  for (long t = 0; t < nt; ++t) r.lr.fibre.insert(r.lr.fibre.end(), {0.0f, 0.6f, 0.8f});
  for (int v = 0; v < r.lr.mesh.X.rows(); ++v) {
    const Vec3 p = r.lr.mesh.X.row(v);
    if ((p.array() < 1e-9).any() || (p.array() > 3 - 1e-9).any()) {
      r.lr.dirichlet.push_back(v);
      r.lr.dirichlet_bone.push_back(1);
    }
  }
  r.surface.resize(1, 3);
  r.surface << 1.5, 1.5, 1.5;
  r.lr.surface.tet = {0};
  r.lr.surface.weights = {0.25f, 0.25f, 0.25f, 0.25f};
  r.lr.surface.outside = {0};
  Muscle m;
  m.name = "block_muscle";
  r.muscles.push_back(m);
  r.jaw.pivot = Vec3(1.5, 1.5, 1.5);
  return r;
}

std::vector<double> perturbed(const std::vector<double>& x, double amount, int seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-amount, amount);
  std::vector<double> y = x;
  for (double& v : y) v += u(rng);
  return y;
}

Controls zero_controls(const SimModel& m) {
  Controls c;
  c.weights.assign(m.num_shapes, 0.0f);
  return c;
}

}  // namespace

TEST(SimCpu, GradientAndHessianMatchFiniteDifferences) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  Controls c = zero_controls(m);
  c.weights[0] = 0.7f;
  c.springs.push_back({m.num_surface / 2, Vec3(0, -3, 12), 2.0});
  const std::vector<double> x = perturbed(m.rest, 0.15, 1);
  // A sphere centred near one surface point, so that it overlaps a few.
  std::vector<double> s;
  embed_surface(m, x, s);
  c.spheres.push_back({Vec3(s[30], s[31], s[32] + 0.3), 1.0, 5.0});
  const FrameInputs in = prepare_frame(m, c);
  std::vector<double> alpha = tet_activations(m, in);
  for (double& a : alpha) a = 0.6;
  std::vector<double> g;
  energy_gradient(m, in, alpha, x, g);
  ElementHessian H;
  element_hessian(m, in, alpha, x, false, H);
  std::mt19937 rng(5);
  std::uniform_int_distribution<int> pick(0, 3 * m.num_nodes - 1);
  const double h = 1e-6;
  double gmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  for (int trial = 0; trial < 12; ++trial) {
    const int i = trial == 0 ? 3 * m.surf_nodes[120] : pick(rng);  // first one certainly touches the surface terms
    std::vector<double> xp = x, xm = x;
    xp[i] += h;
    xm[i] -= h;
    const double fd = (total_energy(m, in, alpha, xp) - total_energy(m, in, alpha, xm)) / (2 * h);
    EXPECT_NEAR(g[i], fd, 1e-6 * gmax) << "dof " << i;
    std::vector<double> gp, gm, e(x.size(), 0.0), Ke;
    energy_gradient(m, in, alpha, xp, gp);
    energy_gradient(m, in, alpha, xm, gm);
    e[i] = 1;
    hessian_product(m, H, e, Ke);
    double kmax = 0, err = 0;
    for (size_t r = 0; r < x.size(); ++r) {
      kmax = std::max(kmax, std::abs(Ke[r]));
      err = std::max(err, std::abs(Ke[r] - (gp[r] - gm[r]) / (2 * h)));
    }
    EXPECT_LT(err, 1e-5 * kmax) << "dof " << i;
    const int node = i / 3, a = i % 3;
    for (int b = 0; b < 3; ++b) EXPECT_NEAR(H.diag[9 * node + 3 * b + a], Ke[3 * node + b], 1e-9 * kmax);
  }
}

TEST(SimCpu, ZeroForcesAtRestWithZeroControls) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  const FrameInputs in = prepare_frame(m, zero_controls(m));
  std::vector<double> g;
  energy_gradient(m, in, tet_activations(m, in), m.rest, g);
  double gmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  const double unit = m.material.shear_modulus() * m.mean_edge * m.mean_edge;  // force of unit strain on one node
  EXPECT_LT(gmax, 1e-10 * unit);
  auto sim = make_cpu_simulator(m);
  const StepStats st = sim->step(zero_controls(m));
  EXPECT_TRUE(st.converged);
  EXPECT_EQ(st.newton_iters, 0);
  // ...but activation does produce forces: the check above can fail.
  Controls c = zero_controls(m);
  c.activations.assign(m.num_muscles, 1.0f);
  const FrameInputs in1 = prepare_frame(m, c);
  energy_gradient(m, in1, tet_activations(m, in1), m.rest, g);
  gmax = 0;
  for (double v : g) gmax = std::max(gmax, std::abs(v));
  EXPECT_GT(gmax, 1e-3 * unit);
}

TEST(SimCpu, PatchTestAffineDeformationHasNoInteriorForces) {
  const Rig r = block_rig();
  SimModel m = make_sim_model(r, Resolution::Low);
  const FrameInputs in = prepare_frame(m, zero_controls(m));
  std::vector<double> alpha(m.num_tets, 0.5);  // uniform activation: still a uniform stress
  Mat3 A;
  A << 1.2, 0.1, -0.05, 0.02, 0.9, 0.1, 0.05, -0.1, 1.1;
  std::vector<double> x(m.rest.size());
  for (int v = 0; v < m.num_nodes; ++v) {
    const Vec3 y = A * Vec3(m.rest[3 * v], m.rest[3 * v + 1], m.rest[3 * v + 2]) + Vec3(0.3, -0.2, 0.1);
    for (int k = 0; k < 3; ++k) x[3 * v + k] = y[k];
  }
  std::vector<double> g;
  energy_gradient(m, in, alpha, x, g);
  double interior = 0, boundary = 0;
  for (int v = 0; v < m.num_nodes; ++v) {
    const double n = Vec3(g[3 * v], g[3 * v + 1], g[3 * v + 2]).norm();
    (m.node_bone[v] ? boundary : interior) = std::max(m.node_bone[v] ? boundary : interior, n);
  }
  EXPECT_LT(interior, 1e-10 * boundary);
  EXPECT_GT(boundary, 1e-2);
}

TEST(SimCpu, PatchTestRigidBoundaryMotionIsReproduced) {
  const Rig r = block_rig();
  const SimModel m = make_sim_model(r, Resolution::Low);
  for (auto& b : const_cast<SimModel&>(m).node_bone)
    if (b) b = 2;  // the whole boundary moves with the "jaw"
  SolverOptions opt;
  opt.newton_tol = 1e-10;
  opt.cg_tol = 1e-10;
  auto sim = make_cpu_simulator(m, opt);
  Controls c = zero_controls(m);
  c.jaw_override = true;
  c.jaw_R = Mat3(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  c.jaw_t = Vec3(0.5, -0.2, 0.3);
  const StepStats st = sim->step(c);
  EXPECT_TRUE(st.converged);
  EXPECT_GT(st.newton_iters, 0);
  std::vector<double> x;
  sim->nodes(x);
  double err = 0;
  for (int v = 0; v < m.num_nodes; ++v) {
    const Vec3 y = c.jaw_R * Vec3(m.rest[3 * v], m.rest[3 * v + 1], m.rest[3 * v + 2]) + c.jaw_t;
    err = std::max(err, (y - Vec3(x[3 * v], x[3 * v + 1], x[3 * v + 2])).norm());
  }
  EXPECT_LT(err, 1e-7);
}

namespace {

int landmark(const Rig& r, const std::string& name) {
  for (size_t i = 0; i < r.landmark_names.size(); ++i)
    if (r.landmark_names[i] == name) return r.landmark_vertex[i];
  return -1;
}

int muscle_index(const SimModel& m, const std::string& name) {
  for (int k = 0; k < m.num_muscles; ++k)
    if (m.muscle_names[k] == name) return k;
  return -1;
}

double mesh_volume(const SimModel& m, const std::vector<double>& x, int only_muscle = -2) {
  double v = 0;
  for (int t = 0; t < m.num_tets; ++t) {
    if (only_muscle > -2 && m.muscle[t] != only_muscle) continue;
    Vec3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = Vec3(&x[3 * size_t(m.tets[4 * t + k])]);
    v += (p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0]) / 6;
  }
  return v;
}

}  // namespace

TEST(SimCpu, ZygomaticusPullsLipCornerUpAndBack) {
  const Rig& rig = fixtures::procedural_rig();
  MaterialParams mat;
  mat.track_stiffness = 0;  // the muscle alone
  const SimModel m = make_sim_model(rig, Resolution::Low, mat);
  const int corner = landmark(rig, "mouth_corner_L");
  const int zyg = muscle_index(m, "zygomaticus_major_L");
  ASSERT_GE(corner, 0);
  ASSERT_GE(zyg, 0);
  auto sim = make_cpu_simulator(m);
  Controls c = zero_controls(m);
  c.activations.assign(m.num_muscles, 0.0f);
  c.activations[zyg] = 1.0f;
  const StepStats st = sim->step(c);
  std::vector<double> s;
  sim->surface(s);
  const Vec3 d = Vec3(&s[3 * corner]) - Vec3(&m.surf_rest[3 * corner]);
  std::printf("lip corner moved (%.3f, %.3f, %.3f) cm; newton %d cg %d rel %.2e %.1f ms\n", d.x(), d.y(), d.z(),
              st.newton_iters, st.cg_iters, st.rel_residual, st.ms);
  EXPECT_TRUE(st.converged);
  EXPECT_GT(d.y(), 0.05);   // up
  EXPECT_LT(d.z(), 0.0);    // back (the face looks along +z)
  EXPECT_GT(d.x(), 0.0);    // toward the subject's left (+x)
}

TEST(SimCpu, VolumeChangeUnderFullActivationBelowTwoPercent) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  auto sim = make_cpu_simulator(m);
  Controls c = zero_controls(m);
  c.activations.assign(m.num_muscles, 1.0f);
  const StepStats st = sim->step(c);
  EXPECT_TRUE(st.converged);
  std::vector<double> x;
  sim->nodes(x);
  const double v0 = mesh_volume(m, m.rest), v1 = mesh_volume(m, x);
  std::printf("volume %.2f -> %.2f cm3 (%.3f%%)\n", v0, v1, 100 * (v1 - v0) / v0);
  EXPECT_LT(std::abs(v1 - v0) / v0, 0.02);
  double worst = 0;
  for (int k = 0; k < m.num_muscles; ++k) {
    const double a = mesh_volume(m, m.rest, k), b = mesh_volume(m, x, k);
    if (a > 0) worst = std::max(worst, std::abs(b - a) / a);
  }
  std::printf("worst muscle volume change %.3f%%\n", 100 * worst);
  EXPECT_LT(worst, 0.02);
}

TEST(SimCpu, NewtonConvergesQuadraticallyNearTheSolution) {
  const SimModel m = make_sim_model(fixtures::procedural_rig(), Resolution::Low);
  SolverOptions opt;
  opt.newton_tol = 1e-10;
  opt.newton_max = 40;
  opt.cg_tol = 1e-10;
  opt.cg_max = 5000;
  auto sim = make_cpu_simulator(m, opt);
  Controls c = zero_controls(m);
  c.activations.assign(m.num_muscles, 0.0f);
  c.activations[muscle_index(m, "zygomaticus_major_L")] = 1.0f;
  c.activations[muscle_index(m, "orbicularis_oris")] = 0.5f;
  const StepStats st = sim->step(c);
  ASSERT_TRUE(st.converged);
  const auto& r = st.residuals;
  ASSERT_GE(r.size(), 3u);
  // The last steps: each residual at most ~ C · previous², with C from the run itself.
  const size_t n = r.size();
  EXPECT_LT(r[n - 1], 1e-10);
  EXPECT_LT(r[n - 1], 10 * r[n - 2] * r[n - 2] / r[0]) << "final step not quadratic";
  EXPECT_LT(st.newton_iters, 20);
}

TEST(SimCpu, LowAndHighResolutionAgreeInBulk) {
  // Material and track stiffness are per volume and per area, so the two
  // meshes of one rig must move the face alike (paper §4).
  const Rig& rig = fixtures::procedural_rig();
  const int corner = landmark(rig, "mouth_corner_L");
  Vec3 d[2];
  for (int res = 0; res < 2; ++res) {
    const SimModel m = make_sim_model(rig, res ? Resolution::High : Resolution::Low);
    auto sim = make_cpu_simulator(m);
    Controls c = zero_controls(m);
    for (int b = 0; b < m.num_shapes; ++b)
      if (m.shape_names[b] == "mouthSmile_L") c.weights[b] = 1.0f;
    const StepStats st = sim->step(c);
    EXPECT_TRUE(st.converged) << (res ? "HR" : "LR");
    std::vector<double> s;
    sim->surface(s);
    d[res] = Vec3(&s[3 * corner]) - Vec3(&m.surf_rest[3 * corner]);
    std::printf("%s: %d tets, lip corner moved (%.3f, %.3f, %.3f) cm in %.0f ms\n", res ? "HR" : "LR", m.num_tets,
                d[res].x(), d[res].y(), d[res].z(), st.ms);
  }
  EXPECT_GT(d[0].dot(d[1]), 0.8 * d[0].norm() * d[1].norm());  // same direction (within ~37°)
  EXPECT_LT(d[1].norm(), 2.0 * d[0].norm());
  EXPECT_GT(d[1].norm(), 0.5 * d[0].norm());
}

TEST(SimCpu, PointSpringPullsAndSpherePushes) {
  const Rig& rig = fixtures::procedural_rig();
  const SimModel m = make_sim_model(rig, Resolution::Low);
  const int corner = landmark(rig, "mouth_corner_L");
  const Vec3 rest(&m.surf_rest[3 * corner]);
  {
    auto sim = make_cpu_simulator(m);
    Controls c = zero_controls(m);
    const Vec3 target = rest + Vec3(1.0, -0.5, 1.0);  // the "candy cane" pull, out and down
    c.springs.push_back({corner, target, 100.0});
    EXPECT_TRUE(sim->step(c).converged);
    std::vector<double> s;
    sim->surface(s);
    const Vec3 p(&s[3 * corner]);
    EXPECT_LT((p - target).norm(), 0.8 * (rest - target).norm());
    EXPECT_GT((p - rest).dot(target - rest), 0.0);
  }
  {
    auto sim = make_cpu_simulator(m);
    Controls c = zero_controls(m);
    // A 2 cm sphere sunk 0.6 cm into the left cheek along the outward direction.
    const int cheek = landmark(rig, "cheek_L") >= 0 ? landmark(rig, "cheek_L") : corner;
    const Vec3 p0(&m.surf_rest[3 * cheek]);
    const Vec3 out = (p0 - Vec3(0, p0.y(), 0)).normalized();
    c.spheres.push_back({p0 + out * (2.0 - 0.6), 2.0, 200.0});
    const StepStats st = sim->step(c);
    EXPECT_TRUE(st.converged);
    std::vector<double> s;
    sim->surface(s);
    const Vec3 p(&s[3 * cheek]);
    EXPECT_LT((p - p0).dot(out), -0.2);  // pushed in
    double deepest = 0;
    for (int v = 0; v < m.num_surface; ++v)
      deepest = std::max(deepest, 2.0 - (Vec3(&s[3 * v]) - c.spheres[0].centre).norm());
    EXPECT_LT(deepest, 0.3);  // the penalty keeps the skin near the sphere surface
  }
}
