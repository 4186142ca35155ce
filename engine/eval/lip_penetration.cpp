#include "eval/lip_penetration.h"

#include <algorithm>

#include "mesh/surface_query.h"
#include "rig/rig_build.h"

namespace facesr {

namespace {

Tris triangles_within(const Tris& F, const std::vector<int>& verts, int num_vertices) {
  std::vector<uint8_t> in(size_t(num_vertices), 0);
  for (int v : verts) in[size_t(v)] = 1;
  std::vector<int> keep;
  for (int t = 0; t < F.rows(); ++t)
    if (in[size_t(F(t, 0))] && in[size_t(F(t, 1))] && in[size_t(F(t, 2))]) keep.push_back(t);
  Tris out(long(keep.size()), 3);
  for (size_t i = 0; i < keep.size(); ++i) out.row(long(i)) = F.row(keep[i]);
  return out;
}

// Depth of p behind the surface (> 0), or 0: the closest point's triangle
// normal tells the side (outward normals, counter-clockwise triangles).
double depth_behind(const SurfaceQuery& q, const Vec3& p, double max_depth) {
  const SurfaceQuery::Closest c = q.closest(p, max_depth);
  if (c.tri < 0 || c.dist <= 0) return 0;
  const auto& V = q.vertices();
  const auto& F = q.triangles();
  const Vec3 a = V.row(F(c.tri, 0)), b = V.row(F(c.tri, 1)), d = V.row(F(c.tri, 2));
  const Vec3 n = (b - a).cross(d - a);
  return (c.point - p).dot(n) > 0 ? c.dist : 0;
}

// Inside a closed mesh by ray parity, then depth = distance to its surface.
double depth_inside(const SurfaceQuery& q, const Vec3& p, double max_depth) {
  const SurfaceQuery::Closest c = q.closest(p, max_depth);
  if (c.tri < 0) return 0;
  // An irrational-looking direction keeps the ray off edges and vertices.
  const std::vector<double> hits = q.all_hits(p, Vec3(0.5377, 0.8318, 0.1367).normalized(), 1e3);
  return hits.size() % 2 == 1 ? c.dist : 0;
}

struct Queries {
  std::unique_ptr<SurfaceQuery> upper_lip, lower_lip;
  const SurfaceQuery *teeth_u = nullptr, *teeth_l = nullptr;
};

Queries make_queries(const LipPenetrationSetup& s, const Points& X) {
  Queries q;
  if (s.upper_tris.rows() > 0) q.upper_lip = std::make_unique<SurfaceQuery>(X, s.upper_tris);
  if (s.lower_tris.rows() > 0) q.lower_lip = std::make_unique<SurfaceQuery>(X, s.lower_tris);
  q.teeth_u = s.teeth_upper_query.get();
  q.teeth_l = s.teeth_lower_query.get();
  return q;
}

// Per lip vertex (upper then lower): lip depth and teeth depth.
void depths(const LipPenetrationSetup& s, const Points& X, const Queries& q, const Eigen::Matrix3d& R,
            const Vec3& t, std::vector<double>& lip, std::vector<double>& teeth) {
  const size_t nu = s.upper.size(), n = nu + s.lower.size();
  lip.assign(n, 0);
  teeth.assign(n, 0);
  for (size_t i = 0; i < n; ++i) {
    const int v = i < nu ? s.upper[i] : s.lower[i - nu];
    const Vec3 p = X.row(v);
    const SurfaceQuery* other = i < nu ? q.lower_lip.get() : q.upper_lip.get();
    if (other) lip[i] = depth_behind(*other, p, s.max_depth_cm);
    double d = 0;
    if (q.teeth_u) d = std::max(d, depth_inside(*q.teeth_u, p, s.max_depth_cm));
    if (q.teeth_l) d = std::max(d, depth_inside(*q.teeth_l, R.transpose() * (p - t), s.max_depth_cm));
    teeth[i] = d;
  }
}

}  // namespace

void finish_lip_penetration_setup(LipPenetrationSetup& s, const Points& rest) {
  if (s.teeth_upper.F.rows() > 0) s.teeth_upper_query = std::make_shared<SurfaceQuery>(s.teeth_upper.V, s.teeth_upper.F);
  if (s.teeth_lower.F.rows() > 0) s.teeth_lower_query = std::make_shared<SurfaceQuery>(s.teeth_lower.V, s.teeth_lower.F);
  const Queries q = make_queries(s, rest);
  std::vector<double> lip, teeth;
  depths(s, rest, q, Eigen::Matrix3d::Identity(), Vec3::Zero(), lip, teeth);
  s.rest_lip.assign(lip.size(), 0);
  s.rest_teeth.assign(teeth.size(), 0);
  for (size_t i = 0; i < lip.size(); ++i) {
    s.rest_lip[i] = lip[i] > 0;
    s.rest_teeth[i] = teeth[i] > 0;
  }
}

LipPenetrationSetup lip_penetration_setup(const Rig& rig) {
  LipPenetrationSetup s;
  lip_vertices(rig, s.upper, s.lower);
  const int M = int(rig.surface.rows());
  s.upper_tris = triangles_within(rig.surface_tris, s.upper, M);
  s.lower_tris = triangles_within(rig.surface_tris, s.lower, M);
  s.teeth_upper = rig.teeth_upper;
  s.teeth_lower = rig.teeth_lower;
  finish_lip_penetration_setup(s, rig.surface);
  return s;
}

LipPenetration lip_penetration(const LipPenetrationSetup& s, const Points& X, const std::array<float, 12>& jaw) {
  Eigen::Matrix3d R;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) R(r, c) = jaw[size_t(3 * r + c)];
  const Vec3 t(jaw[9], jaw[10], jaw[11]);
  const Queries q = make_queries(s, X);
  std::vector<double> lip, teeth;
  depths(s, X, q, R, t, lip, teeth);
  LipPenetration out;
  for (size_t i = 0; i < lip.size(); ++i) {
    if (!(i < s.rest_lip.size() && s.rest_lip[i]) && lip[i] > 0) {
      out.lip_cm = std::max(out.lip_cm, lip[i]);
      ++out.lip_vertices;
    }
    if (!(i < s.rest_teeth.size() && s.rest_teeth[i]) && teeth[i] > 0) {
      out.teeth_cm = std::max(out.teeth_cm, teeth[i]);
      ++out.teeth_vertices;
    }
  }
  return out;
}

}  // namespace facesr
