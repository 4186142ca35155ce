#include "mesh/remesh.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#include "core/error.h"

namespace facesr {
namespace {
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using SM = CGAL::Surface_mesh<K::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

SM to_cgal(const TriMesh& m) {
  SM sm;
  std::vector<SM::Vertex_index> vi(m.V.rows());
  for (int i = 0; i < m.V.rows(); ++i) vi[i] = sm.add_vertex(K::Point_3(m.V(i, 0), m.V(i, 1), m.V(i, 2)));
  for (int f = 0; f < m.F.rows(); ++f) {
    const auto face = sm.add_face(vi[m.F(f, 0)], vi[m.F(f, 1)], vi[m.F(f, 2)]);
    require(face != SM::null_face(), "remesh: input is not an oriented 2-manifold (face " +
                                         std::to_string(f) + ")");
  }
  return sm;
}

TriMesh from_cgal(const SM& sm) {
  TriMesh m;
  std::vector<int> map(sm.num_vertices() + sm.number_of_removed_vertices(), -1);
  m.V.resize(long(sm.number_of_vertices()), 3);
  int n = 0;
  for (auto v : sm.vertices()) {
    const auto& p = sm.point(v);
    m.V.row(n) = Vec3(p.x(), p.y(), p.z()).transpose();
    map[v.idx()] = n++;
  }
  m.F.resize(long(sm.number_of_faces()), 3);
  int f = 0;
  for (auto face : sm.faces()) {
    int k = 0;
    for (auto v : vertices_around_face(sm.halfedge(face), sm)) m.F(f, k++) = map[v.idx()];
    ++f;
  }
  return m;
}
}  // namespace

TriMesh remesh_isotropic(const TriMesh& in, double target_edge, int iterations) {
  SM sm = to_cgal(in);
  PMP::remove_degenerate_faces(sm);
  PMP::isotropic_remeshing(faces(sm), target_edge, sm,
                           PMP::parameters::number_of_iterations(iterations).protect_constraints(false));
  sm.collect_garbage();
  return from_cgal(sm);
}

RepairReport repair_self_intersections(TriMesh& m, int max_rounds) {
  RepairReport rep;
  const Points original = m.V;
  std::vector<std::vector<int>> nbr(m.V.rows());
  for (int f = 0; f < m.F.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      for (int j = 1; j < 3; ++j) nbr[m.F(f, k)].push_back(m.F(f, (k + j) % 3));
  std::vector<uint8_t> touched(m.V.rows(), 0);
  for (int round = 0; round < max_rounds; ++round) {
    SM sm = to_cgal(m);
    std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
    PMP::self_intersections(faces(sm), sm, std::back_inserter(pairs));
    if (round == 0) rep.initial_pairs = long(pairs.size());
    if (pairs.empty()) break;
    require(round + 1 < max_rounds, "self-intersection repair did not converge (" +
                                        std::to_string(pairs.size()) + " intersecting triangle pairs left)");
    std::vector<uint8_t> sel(m.V.rows(), 0);
    for (const auto& p : pairs)
      for (auto f : {p.first, p.second})
        for (int k = 0; k < 3; ++k) sel[m.F(int(f.idx()), k)] = 1;
    std::vector<uint8_t> grow = sel;
    for (int v = 0; v < m.V.rows(); ++v)
      if (sel[v])
        for (int w : nbr[v]) grow[w] = 1;
    Points next = m.V;
    for (int v = 0; v < m.V.rows(); ++v) {
      if (!grow[v] || nbr[v].empty()) continue;
      Vec3 c = Vec3::Zero();
      for (int w : nbr[v]) c += m.V.row(w).transpose();
      c /= double(nbr[v].size());
      next.row(v) = 0.5 * m.V.row(v) + 0.5 * c.transpose();
      touched[v] = 1;
    }
    m.V = next;
  }
  for (int v = 0; v < m.V.rows(); ++v)
    if (touched[v]) {
      rep.moved++;
      rep.max_displacement = std::max(rep.max_displacement, (m.V.row(v) - original.row(v)).norm());
    }
  return rep;
}

SurfaceCheck check_surface(const TriMesh& m) {
  SM sm = to_cgal(m);
  SurfaceCheck c;
  c.closed = CGAL::is_closed(sm);
  c.self_intersects = PMP::does_self_intersect(sm);
  auto fccmap = sm.add_property_map<SM::Face_index, std::size_t>("f:CC").first;
  c.components = long(PMP::connected_components(sm, fccmap));
  return c;
}

}  // namespace facesr
