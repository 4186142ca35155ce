#include "rig/procedural_head.h"

#include <cmath>

#include <Eigen/Geometry>

#include "core/error.h"
#include "mesh/grid.h"
#include "mesh/marching_tets.h"
#include "mesh/remesh.h"

namespace facesr {
namespace {

// Head layout in cm; +x subject's left, +y up, +z out of the face.
const double kMouthY = -4.6;        // height of the lip line
const Vec3 kJawPivot(0, -0.5, -0.5);  // near the temporomandibular joints
const double kNeckCutY = -15.0;

double ellipsoid(const Vec3& p, const Vec3& c, const Vec3& r) {
  // Scaled-sphere distance: exact zero set, approximate distance elsewhere,
  // which is all the iso-surface extraction needs.
  const Vec3 q = (p - c).cwiseQuotient(r);
  return (q.norm() - 1.0) * r.minCoeff();
}
double smin(double a, double b, double k) {
  const double h = std::clamp(0.5 + 0.5 * (b - a) / k, 0.0, 1.0);
  return b * (1 - h) + a * h - k * h * (1 - h);
}
double smax(double a, double b, double k) { return -smin(-a, -b, k); }
double smoothstep(double e0, double e1, double x) {
  const double t = std::clamp((x - e0) / (e1 - e0), 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

double mouth_cavity(const Vec3& p) { return ellipsoid(p, Vec3(0, kMouthY, 6.0), Vec3(2.8, 1.1, 2.6)); }
double mouth_slit(const Vec3& p) {
  return std::max({std::abs(p.y() - kMouthY) - 0.25, std::abs(p.x()) - 2.3, 6.0 - p.z()});
}
double neck(const Vec3& p) {
  const double r = std::hypot(p.x(), p.z() + 0.5) - 5.0;
  return std::max({r, kNeckCutY - p.y(), p.y() - (-3.0)});
}

double head_sdf(const Vec3& p) {
  double d = ellipsoid(p, Vec3(0, 3, 0), Vec3(7.8, 9.5, 9.2));          // cranium
  d = smin(d, ellipsoid(p, Vec3(0, -4.5, 2.5), Vec3(6.2, 6.0, 6.8)), 1.0);  // face and jaw
  d = smin(d, ellipsoid(p, Vec3(0, 3.5, 7.8), Vec3(5.0, 1.2, 1.6)), 0.6);   // brow ridge
  d = smin(d, ellipsoid(p, Vec3(0, -0.5, 9.3), Vec3(1.1, 2.0, 1.4)), 0.5);  // nose
  d = smin(d, ellipsoid(p, Vec3(3.8, -1.5, 6.3), Vec3(2.4, 2.2, 2.2)), 0.8);  // cheeks
  d = smin(d, ellipsoid(p, Vec3(-3.8, -1.5, 6.3), Vec3(2.4, 2.2, 2.2)), 0.8);
  d = smin(d, ellipsoid(p, Vec3(0, -8.8, 6.6), Vec3(2.4, 1.6, 1.8)), 0.8);    // chin
  d = smin(d, ellipsoid(p, Vec3(0, -4.1, 8.9), Vec3(2.6, 0.55, 0.7)), 0.3);   // upper lip
  d = smin(d, ellipsoid(p, Vec3(0, -5.1, 8.8), Vec3(2.5, 0.6, 0.7)), 0.3);    // lower lip
  d = smin(d, neck(p), 1.0);
  d = std::max(d, kNeckCutY - p.y());  // flat neck cut
  d = smax(d, -mouth_cavity(p), 0.15);
  d = smax(d, -mouth_slit(p), 0.15);
  return d;
}

double teeth_sdf(const Vec3& p, double yc) {
  const double r = std::hypot(p.x(), p.z() - 5.0);
  return std::max({std::abs(r - 1.8) - 0.25, std::abs(p.y() - yc) - 0.25, 5.6 - p.z()});
}

TriMesh implicit_surface(double (*f)(const Vec3&, double), double arg, const Vec3& lo, const Vec3& hi,
                         double h, double edge) {
  const Grid g = Grid::covering(lo, hi, h, 2);
  std::vector<float> v(g.size());
  for (int k = 0; k < g.nz; ++k)
    for (int j = 0; j < g.ny; ++j)
      for (int i = 0; i < g.nx; ++i) v[g.index(i, j, k)] = float(f(g.node(i, j, k), arg));
  return remesh_isotropic(marching_tets(g, v), edge, 3);
}

// Jaw skinning weight: 1 on the chin and lower lip, 0 on the upper lip and
// above, with a transition that widens away from the mouth corners.
double jaw_weight(const Vec3& p) {
  const double beyond = std::max(0.0, std::abs(p.x()) - 2.3);
  const double band = 0.15 + 0.8 * beyond;
  double w = smoothstep(-band, band, kMouthY - p.y());
  w *= smoothstep(-1.0, 2.0, p.z());          // not the back of the head
  w *= smoothstep(kNeckCutY + 2.0, -10.5, p.y());  // not the neck base
  return w;
}

struct RigidT {
  Mat3 R;
  Vec3 t;
};
RigidT jaw_transform(const std::string& name) {
  const double deg = M_PI / 180.0;
  RigidT T{Mat3::Identity(), Vec3::Zero()};
  auto about_pivot = [&](const Mat3& R) { T.R = R; T.t = kJawPivot - R * kJawPivot; };
  if (name == "jawOpen") about_pivot(Eigen::AngleAxisd(18 * deg, Vec3::UnitX()).toRotationMatrix());
  if (name == "jawLeft") about_pivot(Eigen::AngleAxisd(6 * deg, Vec3::UnitY()).toRotationMatrix());
  if (name == "jawRight") about_pivot(Eigen::AngleAxisd(-6 * deg, Vec3::UnitY()).toRotationMatrix());
  if (name == "jawForward") T.t = Vec3(0, 0, 0.5);
  return T;
}

double gauss(const Vec3& p, const Vec3& c, double s) { return std::exp(-(p - c).squaredNorm() / (2 * s * s)); }

}  // namespace

HeadSource make_procedural_head(const ProceduralOptions& opt) {
  require(opt.grid_h > 0.02 && opt.grid_h <= 0.4, "procedural head: grid_h must be in (0.02, 0.4] cm");
  require(opt.edge >= opt.grid_h && opt.edge <= 1.5, "procedural head: edge must be in [grid_h, 1.5] cm");
  HeadSource src;
  src.name = "procedural";
  auto head = [](const Vec3& p, double) { return head_sdf(p); };
  src.skin = implicit_surface(head, 0, Vec3(-9, kNeckCutY - 0.5, -10), Vec3(9, 13, 11.5), opt.grid_h, opt.edge);
  const auto teeth = [](const Vec3& p, double yc) { return teeth_sdf(p, yc); };
  src.teeth_upper = implicit_surface(teeth, -4.2, Vec3(-2.3, -4.6, 5.3), Vec3(2.3, -3.8, 7.3), 0.08, 0.18);
  src.teeth_lower = implicit_surface(teeth, -5.0, Vec3(-2.3, -5.4, 5.3), Vec3(2.3, -4.6, 7.3), 0.08, 0.18);

  const int n = int(src.skin.V.rows());
  const Points N = vertex_normals(src.skin.V, src.skin.F);
  src.region.resize(n);
  for (int v = 0; v < n; ++v) {
    const Vec3 p = src.skin.V.row(v);
    SkinRegion r = SkinRegion::Head;
    if (p.y() < kNeckCutY + 0.05) r = SkinRegion::NeckCap;
    else if (mouth_cavity(p) > -0.3 && mouth_cavity(p) < 0.3 && p.z() < 8.2) r = SkinRegion::Mouth;
    else if (std::abs(p.y() - kMouthY) < 0.3 && std::abs(p.x()) < 2.3 && p.z() < 8.4) r = SkinRegion::Mouth;
    else if (p.z() > 3.0 && p.y() > -11.5 && p.y() < 8.0 && std::abs(p.x()) < 7.0) r = SkinRegion::Face;
    src.region[v] = r;
    if (r == SkinRegion::Face) src.face_vertices.push_back(v);
  }

  // Blendshapes.
  auto add = [&](const std::string& name, auto&& field) {
    Points d(n, 3);
    for (int v = 0; v < n; ++v) d.row(v) = field(Vec3(src.skin.V.row(v)), Vec3(N.row(v))).transpose();
    src.blendshape_names.push_back(name);
    src.blendshape_deltas.push_back(std::move(d));
  };
  for (const std::string name : {"jawOpen", "jawLeft", "jawRight", "jawForward"}) {
    const RigidT T = jaw_transform(name);
    add(name, [&](const Vec3& p, const Vec3&) { return Vec3(jaw_weight(p) * (T.R * p + T.t - p)); });
    Points teeth = src.teeth_lower.V;
    for (int i = 0; i < teeth.rows(); ++i) teeth.row(i) = (T.R * Vec3(teeth.row(i)) + T.t).transpose();
    src.jaw_shape_lower_teeth.emplace_back(name, std::move(teeth));
  }
  for (int s = 0; s < 2; ++s) {
    const double sx = s == 0 ? 1.0 : -1.0;  // _L is +x
    const std::string side = s == 0 ? "_L" : "_R";
    const Vec3 corner(2.35 * sx, kMouthY, 8.3);
    add("mouthSmile" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, corner, 1.2) * Vec3(0.35 * sx, 0.75, -0.45)); });
    add("mouthFrown" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, corner, 1.1) * Vec3(0.1 * sx, -0.5, -0.1)); });
    add("browInnerUp" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(1.2 * sx, 3.6, 9.0), 0.9) * Vec3(0, 0.55, 0)); });
    add("browDown" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(2.9 * sx, 4.0, 8.7), 1.2) * Vec3(-0.15 * sx, -0.4, 0)); });
    add("browOuterUp" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(4.8 * sx, 3.5, 7.6), 1.0) * Vec3(0, 0.5, 0)); });
    add("cheekPuff" + side, [&](const Vec3& p, const Vec3& nrm) { return Vec3(gauss(p, Vec3(3.6 * sx, -3.5, 7.0), 1.3) * 0.6 * nrm); });
    add("mouthUpperUp" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(0.8 * sx, -4.2, 9.3), 0.7) * Vec3(0, 0.35, 0.05)); });
    add("mouthLowerDown" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(0.8 * sx, -5.0, 9.2), 0.7) * Vec3(0, -0.35, 0.05)); });
    add("noseSneer" + side, [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, Vec3(1.0 * sx, -1.5, 9.4), 0.7) * Vec3(0, 0.3, 0)); });
  }
  const Vec3 mouth(0, kMouthY, 9.0);
  add("mouthPucker", [&](const Vec3& p, const Vec3&) { return Vec3(gauss(p, mouth, 1.3) * Vec3(-0.3 * p.x(), 0, 0.5)); });
  add("mouthFunnel", [&](const Vec3& p, const Vec3&) {
    return Vec3(gauss(p, mouth, 1.3) * Vec3(-0.15 * p.x(), 0.35 * std::tanh(3 * (p.y() - kMouthY)), 0.35));
  });

  // Landmarks: analytic positions snapped to the nearest face vertex.
  auto snap = [&](const Vec3& q) {
    int best = -1;
    double bd = 1e300;
    for (int v : src.face_vertices) {
      const double d = (Vec3(src.skin.V.row(v)) - q).squaredNorm();
      if (d < bd) bd = d, best = v;
    }
    return best;
  };
  auto pair = [&](const std::string& name, const Vec3& left) {
    src.landmarks[name + "_L"] = snap(left);
    src.landmarks[name + "_R"] = snap(Vec3(-left.x(), left.y(), left.z()));
  };
  pair("mouth_corner", Vec3(2.35, kMouthY, 8.3));
  pair("upper_lip_peak", Vec3(0.6, -4.0, 9.5));
  pair("lower_lip_side", Vec3(1.2, -5.2, 9.2));
  pair("jaw_lower", Vec3(3.5, -9.0, 5.0));
  pair("jaw_angle", Vec3(5.5, -7.0, 1.0));
  pair("jaw_upper", Vec3(6.2, -3.5, 0.5));
  pair("jaw_top", Vec3(6.8, 0.0, -0.5));
  pair("nostril", Vec3(0.9, -2.2, 9.6));
  pair("eye_outer", Vec3(4.3, 1.8, 7.5));
  pair("eye_inner", Vec3(1.4, 1.8, 8.3));
  pair("eye_top", Vec3(2.8, 2.4, 8.2));
  pair("eye_bottom", Vec3(2.8, 1.2, 8.2));
  pair("brow_inner", Vec3(1.2, 3.6, 9.0));
  pair("brow_mid", Vec3(2.9, 4.0, 8.7));
  pair("brow_outer", Vec3(4.8, 3.5, 7.6));
  src.landmarks["chin"] = snap(Vec3(0, -10.0, 7.0));
  src.landmarks["nasion"] = snap(Vec3(0, 3.0, 9.2));
  src.landmarks["nose_tip"] = snap(Vec3(0, -0.8, 10.8));
  src.landmarks["subnasale"] = snap(Vec3(0, -2.6, 9.8));
  src.landmarks["upper_lip_top"] = snap(Vec3(0, -4.0, 9.6));
  src.landmarks["lower_lip_bottom"] = snap(Vec3(0, -5.3, 9.5));
  src.landmarks["upper_lip_inner"] = snap(Vec3(0, -4.4, 9.4));
  src.landmarks["lower_lip_inner"] = snap(Vec3(0, -4.8, 9.4));
  for (int k = 0; k < 6; ++k) {
    const double a = 2 * M_PI * k / 6;
    const Vec3 c(2.85 + 1.5 * std::cos(a), 1.8 + 0.6 * std::sin(a), 8.0);
    src.landmarks["eye_ring_L_" + std::to_string(k)] = snap(c);
    src.landmarks["eye_ring_R_" + std::to_string(k)] = snap(Vec3(-c.x(), c.y(), c.z()));
  }
  for (int k = 0; k < 12; ++k) {
    const double a = k <= 6 ? M_PI - k * M_PI / 6 : -(k - 6) * M_PI / 6;
    src.landmarks["mouth_ring_" + std::to_string(k)] =
        snap(Vec3(2.35 * std::cos(a), kMouthY + 0.7 * std::sin(a), 9.0));
  }
  return src;
}

}  // namespace facesr
