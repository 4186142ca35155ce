#include "sim/sim_model.h"

#include <Eigen/Dense>
#include <cmath>

#include "core/error.h"

namespace facesr {

Resolution parse_resolution(const std::string& s) {
  if (s == "low" || s == "lr") return Resolution::Low;
  if (s == "high" || s == "hr") return Resolution::High;
  throw Error("unknown resolution '" + s + "' (expected low or high)");
}

const char* resolution_name(Resolution r) { return r == Resolution::Low ? "low" : "high"; }

namespace {

// Node → slot lists by counting sort.
SimModel::Incidence make_incidence(const SimModel& m, const std::vector<int32_t>& vertices) {
  SimModel::Incidence inc;
  inc.vertices = vertices;
  const int nslots = 4 * (m.num_tets + int(vertices.size()));
  auto slot_node = [&](int s) {
    return s < 4 * m.num_tets ? m.tets[s] : m.surf_nodes[4 * vertices[(s - 4 * m.num_tets) / 4] + s % 4];
  };
  inc.offset.assign(m.num_nodes + 1, 0);
  for (int s = 0; s < nslots; ++s) ++inc.offset[slot_node(s) + 1];
  for (int v = 0; v < m.num_nodes; ++v) inc.offset[v + 1] += inc.offset[v];
  inc.slot.resize(nslots);
  std::vector<int32_t> fill(inc.offset.begin(), inc.offset.end() - 1);
  for (int s = 0; s < nslots; ++s) inc.slot[fill[slot_node(s)]++] = s;
  return inc;
}

}  // namespace

SimModel make_sim_model(const Rig& rig, Resolution res, const MaterialParams& material) {
  const SimMesh& sm = res == Resolution::Low ? rig.lr : rig.hr;
  const std::string what = std::string("rig '") + rig.name + "' " + resolution_name(res) + " mesh";
  require(sm.mesh.T.rows() > 0, what + ": no tetrahedra");
  SimModel m;
  m.res = res;
  m.material = material;
  m.num_nodes = int(sm.mesh.X.rows());
  m.num_tets = int(sm.mesh.T.rows());
  m.num_surface = rig.num_surface_vertices();
  m.num_muscles = int(rig.muscles.size());
  m.num_shapes = rig.num_blendshapes();

  m.rest.resize(3 * size_t(m.num_nodes));
  for (int v = 0; v < m.num_nodes; ++v)
    for (int k = 0; k < 3; ++k) m.rest[3 * v + k] = sm.mesh.X(v, k);
  m.tets.resize(4 * size_t(m.num_tets));
  m.Dminv.resize(9 * size_t(m.num_tets));
  m.volume.resize(m.num_tets);
  m.fibre.resize(3 * size_t(m.num_tets));
  m.phi.resize(m.num_tets);
  m.muscle.resize(m.num_tets);
  double edge_sum = 0;
  for (int t = 0; t < m.num_tets; ++t) {
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 4; ++k) m.tets[4 * t + k] = sm.mesh.T(t, k);
    const Vec3 x0 = sm.mesh.X.row(sm.mesh.T(t, 0));
    for (int c = 0; c < 3; ++c) Dm.col(c) = Vec3(sm.mesh.X.row(sm.mesh.T(t, c + 1))) - x0;
    const double det = Dm.determinant();
    require(det > 0 && std::isfinite(det), what + ": tet " + std::to_string(t) + " is inverted or degenerate at rest");
    const Eigen::Matrix3d inv = Dm.inverse();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.Dminv[9 * t + 3 * i + j] = inv(i, j);
    m.volume[t] = det / 6;
    edge_sum += Dm.col(0).norm() + Dm.col(1).norm() + Dm.col(2).norm();
    const int mu = sm.muscle[t];
    m.muscle[t] = mu;
    m.phi[t] = mu >= 0 ? std::clamp(double(sm.muscle_fraction[t]), 0.0, 1.0) : 0.0;
    Vec3 a(sm.fibre[3 * t], sm.fibre[3 * t + 1], sm.fibre[3 * t + 2]);
    if (a.norm() < 1e-6) {
      a = Vec3::UnitX();
      m.phi[t] = 0;  // no fibre direction: passive flesh
    }
    a.normalize();
    for (int k = 0; k < 3; ++k) m.fibre[3 * t + k] = a[k];
  }
  m.mean_edge = edge_sum / (3.0 * m.num_tets);

  m.node_bone.assign(m.num_nodes, 0);
  for (size_t i = 0; i < sm.dirichlet.size(); ++i) m.node_bone[sm.dirichlet[i]] = sm.dirichlet_bone[i] ? 2 : 1;

  m.surf_nodes.resize(4 * size_t(m.num_surface));
  m.surf_weights.resize(4 * size_t(m.num_surface));
  m.surf_rest.assign(3 * size_t(m.num_surface), 0.0);
  for (int v = 0; v < m.num_surface; ++v) {
    const int t = sm.surface.tet[v];
    for (int k = 0; k < 4; ++k) {
      const int n = sm.mesh.T(t, k);
      const double w = sm.surface.weights[4 * v + k];
      m.surf_nodes[4 * v + k] = n;
      m.surf_weights[4 * v + k] = w;
      for (int c = 0; c < 3; ++c) m.surf_rest[3 * v + c] += w * sm.mesh.X(n, c);
    }
  }
  m.track_k.assign(m.num_surface, 0.0);
  for (size_t i = 0; i < sm.tracks.size(); ++i)
    m.track_k[sm.tracks[i]] += material.track_stiffness * sm.track_area[i];

  m.shape_names = rig.blendshape_names;
  for (const auto& mu : rig.muscles) m.muscle_names.push_back(mu.name);
  m.shape_deltas = rig.blendshape_deltas;
  m.activation = rig.activation;
  m.jaw = rig.jaw;
  Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
  for (int v = 0; v < m.num_surface; ++v) {
    lo = lo.cwiseMin(Vec3(rig.surface.row(v)));
    hi = hi.cwiseMax(Vec3(rig.surface.row(v)));
  }
  m.face_size = (hi - lo).norm();

  std::vector<int32_t> all(m.num_surface), tracked;
  for (int v = 0; v < m.num_surface; ++v) {
    all[v] = v;
    if (m.track_k[v] > 0) tracked.push_back(v);
  }
  m.inc_all = make_incidence(m, all);
  m.inc_tracked = make_incidence(m, tracked);
  return m;
}

}  // namespace facesr
