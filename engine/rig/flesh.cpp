#include "rig/flesh.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <queue>

#include "core/error.h"
#include "mesh/marching_tets.h"
#include "mesh/remesh.h"
#include "rig/jaw_fit.h"

namespace facesr {

namespace {
struct DepthSample {
  const char* landmark;
  Vec3 offset;   // cm, for the subject's left; mirrored for _R
  double depth;  // cm
};
// Facial soft-tissue thickness, rounded means for adult males of normal BMI
// from De Greef et al. 2006, "Large-scale in-vivo Caucasian facial soft
// tissue thickness database for craniofacial reconstruction", Forensic
// Science International 159S, S126–S146 (table 3). Nose tip and lips have no
// bone beneath; their large depths keep them all flesh (cartilage included).
const DepthSample kDepths[] = {
    {"nasion", {0, 0, 0}, 0.65},          {"brow_inner_L", {-0.6, 0.4, 0}, 0.55},  // glabella
    {"brow_mid_L", {0, 3.0, 0}, 0.45},    // frontal eminence
    {"brow_mid_L", {0, 0, 0}, 0.65},      // supraorbital
    {"eye_bottom_L", {0, -0.7, 0}, 0.65},  // suborbital
    {"eye_outer_L", {0.3, 0, 0}, 0.7},     // lateral orbit
    {"eye_outer_L", {0.8, -1.6, 0}, 0.75},  // zygomatic arch
    {"eye_bottom_L", {0.4, -2.2, 0}, 1.5},  // inferior malar
    {"nose_tip", {0, 0, 0}, 1.2},         {"subnasale", {0, 0, 0}, 1.5},
    {"upper_lip_top", {0, 0, 0}, 1.3},    {"lower_lip_bottom", {0, 0, 0}, 1.35},
    {"mouth_corner_L", {0, 0, 0}, 1.4},   {"mouth_corner_L", {2.0, 0.4, 0}, 2.4},  // buccal (supra/sub M2)
    {"chin", {0, 1.0, 0}, 1.15},          // labiomental fold / mental eminence
    {"chin", {0, 0, 0}, 1.05},            {"chin", {0, -1.0, 0}, 0.75},  // menton
    {"jaw_upper_L", {0, 0, 0}, 1.9},      // mid-masseter
    {"jaw_angle_L", {0, 0, 0}, 1.4},      // gonion
    {"jaw_lower_L", {0, 0, 0}, 1.1},
};
constexpr double kDefaultDepth = 0.6;  // scalp and neck away from facial landmarks
constexpr double kSigma = 1.4;         // cm, interpolation radius

std::string mirror_name(const std::string& n) {
  if (n.size() > 2 && n.compare(n.size() - 2, 2, "_L") == 0) return n.substr(0, n.size() - 2) + "_R";
  return n;
}
}  // namespace

ThicknessField::ThicknessField(const HeadSource& src) {
  for (const auto& s : kDepths) {
    for (int side = 0; side < 2; ++side) {
      const std::string name = side == 0 ? s.landmark : mirror_name(s.landmark);
      if (side == 1 && name == s.landmark && s.offset.x() == 0) continue;  // central sample once
      auto it = src.landmarks.find(name);
      require(it != src.landmarks.end(), src.name + ": landmark '" + name + "' is missing");
      Vec3 off = s.offset;
      if (side == 1) off.x() = -off.x();
      pos_.push_back(Vec3(src.skin.V.row(it->second)) + off);
      depth_.push_back(s.depth);
    }
  }
}

double ThicknessField::at(const Vec3& p) const {
  double wsum = 0.05, dsum = 0.05 * kDefaultDepth;
  for (size_t i = 0; i < pos_.size(); ++i) {
    const double w = std::exp(-(p - pos_[i]).squaredNorm() / (2 * kSigma * kSigma));
    wsum += w;
    dsum += w * depth_[i];
  }
  return dsum / wsum;
}

FleshDomain::FleshDomain(const HeadSource& src, const Jaw& jaw, double grid_h, bool verbose) : src_(src) {
  skin_q_ = std::make_unique<SurfaceQuery>(src.skin.V, src.skin.F);
  Vec3 lo, hi;
  bounding_box(src.skin.V, lo, hi);
  grid_ = Grid::covering(lo, hi, grid_h, 3);
  if (verbose)
    std::fprintf(stderr, "[rig] flesh grid %dx%dx%d (h = %.2f cm)\n", grid_.nx, grid_.ny, grid_.nz, grid_h);
  sd_ = signed_distance_grid(*skin_q_, grid_, 4.0);
  const ThicknessField thick(src);
  bone_.resize(sd_.size());
#pragma omp parallel for schedule(dynamic, 4096)
  for (long i = 0; i < long(sd_.size()); ++i) {
    const int x = int(i % grid_.nx), y = int((i / grid_.nx) % grid_.ny), z = int(i / (long(grid_.nx) * grid_.ny));
    bone_[i] = sd_[i] < -0.1f ? float(sd_[i] + thick.at(grid_.node(x, y, z))) : 1.0f;
  }
  // Jaw weight of each skin vertex: the fraction of the jaw's rigid jawOpen
  // motion that the jawOpen blendshape applies there.
  skin_w_.assign(src.skin.V.rows(), 0.0);
  const auto it = std::find(src.blendshape_names.begin(), src.blendshape_names.end(), "jawOpen");
  const JawShape* open = nullptr;
  for (const auto& s : jaw.shapes)
    if (s.name == "jawOpen") open = &s;
  if (it != src.blendshape_names.end() && open) {
    const Points& d = src.blendshape_deltas[it - src.blendshape_names.begin()];
    for (int v = 0; v < src.skin.V.rows(); ++v) {
      const Vec3 x = src.skin.V.row(v);
      const Vec3 r = open->R * x + open->t - x;
      if (r.norm() < 0.05) continue;  // near the hinge the ratio is meaningless
      skin_w_[v] = std::clamp(Vec3(d.row(v)).dot(r) / r.squaredNorm(), 0.0, 1.0);
    }
  }
}

double FleshDomain::trilinear(const std::vector<float>& f, const Vec3& p) const {
  const Vec3 q = (p - grid_.origin) / grid_.h;
  const int i = std::clamp(int(std::floor(q.x())), 0, grid_.nx - 2);
  const int j = std::clamp(int(std::floor(q.y())), 0, grid_.ny - 2);
  const int k = std::clamp(int(std::floor(q.z())), 0, grid_.nz - 2);
  const double u = std::clamp(q.x() - i, 0.0, 1.0), v = std::clamp(q.y() - j, 0.0, 1.0),
               w = std::clamp(q.z() - k, 0.0, 1.0);
  double s = 0;
  for (int c = 0; c < 8; ++c) {
    const int di = c & 1, dj = (c >> 1) & 1, dk = (c >> 2) & 1;
    s += (di ? u : 1 - u) * (dj ? v : 1 - v) * (dk ? w : 1 - w) * f[grid_.index(i + di, j + dj, k + dk)];
  }
  return s;
}

double FleshDomain::sd(const Vec3& p) const { return trilinear(sd_, p); }
double FleshDomain::bone(const Vec3& p) const { return trilinear(bone_, p); }

int FleshDomain::nearest_skin_vertex(const Vec3& p) const {
  const auto c = skin_q_->closest(p);
  int k;
  c.bary.maxCoeff(&k);
  return src_.skin.F(c.tri, k);
}

double FleshDomain::jaw_weight(const Vec3& p) const {
  const auto c = skin_q_->closest(p);
  double w = 0;
  for (int k = 0; k < 3; ++k) w += c.bary[k] * skin_w_[src_.skin.F(c.tri, k)];
  return w;
}

namespace {
// Drops small shells (isolated bone specks where the thickness field dips):
// they would only make tiny cavities in the flesh.
TriMesh drop_small_shells(const TriMesh& m, double min_area, int& shells, int& kept) {
  const std::vector<int> comp = face_components(m.F, m.V.rows(), shells);
  std::vector<double> area(shells, 0.0);
  for (int f = 0; f < m.F.rows(); ++f) {
    const Vec3 a = m.V.row(m.F(f, 0)), b = m.V.row(m.F(f, 1)), c = m.V.row(m.F(f, 2));
    area[comp[f]] += 0.5 * (b - a).cross(c - a).norm();
  }
  kept = int(std::count_if(area.begin(), area.end(), [&](double a) { return a >= min_area; }));
  std::vector<int> keep_v(m.V.rows(), -1);
  std::vector<Vec3i> tris;
  int nv = 0;
  Points V(m.V.rows(), 3);
  for (int f = 0; f < m.F.rows(); ++f) {
    if (area[comp[f]] < min_area) continue;
    Vec3i t;
    for (int k = 0; k < 3; ++k) {
      int& id = keep_v[m.F(f, k)];
      if (id < 0) V.row(id = nv++) = m.V.row(m.F(f, k));
      t[k] = id;
    }
    tris.push_back(t);
  }
  TriMesh out;
  out.V = V.topRows(nv);
  out.F.resize(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) out.F.row(long(t)) = tris[t].cast<int32_t>().transpose();
  return out;
}

std::vector<float> blur_indicator(const Grid& grid, std::vector<float> g, int passes) {
  for (int it = 0; it < passes; ++it) {
    std::vector<float> next = g;
#pragma omp parallel for schedule(static)
    for (int k = 1; k < grid.nz - 1; ++k)
      for (int j = 1; j < grid.ny - 1; ++j)
        for (int i = 1; i < grid.nx - 1; ++i) {
          const long c = grid.index(i, j, k);
          next[c] = 0.4f * g[c] + 0.1f * (g[c - 1] + g[c + 1] + g[c - grid.nx] + g[c + grid.nx] +
                                          g[c - long(grid.nx) * grid.ny] + g[c + long(grid.nx) * grid.ny]);
        }
    g.swap(next);
  }
  return g;
}
}  // namespace

TriMesh FleshDomain::bone_surface(double edge, bool verbose) const {
  const double min_area = 4.0;  // cm²
  // Thin bone plates where two thickness bands nearly meet are artefacts of
  // the thickness field, and remeshing folds them into themselves. A little
  // blur removes most; when the folds survive repair, a stronger blur
  // (thicker, smoother plates) is tried before giving up on a remeshed
  // surface. The unremeshed level set (which cannot self-intersect) is not a
  // fallback: it is ~30x finer than the target edge and TetGen's quality
  // refinement on it did not finish in 15 minutes (identity head, seed 16).
  std::string last_error;
  for (const int passes : {2, 4, 8}) {
    const TriMesh raw = marching_tets(grid_, blur_indicator(grid_, bone_, passes));
    require(raw.F.rows() > 0, src_.name + ": no bone found under the skin (is the head too thin?)");
    int shells = 0, kept = 0;
    TriMesh out = drop_small_shells(remesh_isotropic(raw, edge, 3), min_area, shells, kept);
    RepairReport rep;
    try {
      rep = repair_self_intersections(out);
    } catch (const Error& e) {
      last_error = e.what();
      if (verbose)
        std::fprintf(stderr, "[rig] bone surface (blur %d): %s; retrying with a stronger blur\n", passes, e.what());
      continue;
    }
    if (verbose && rep.initial_pairs > 0)
      std::fprintf(stderr, "[rig] bone surface: repaired %ld self-intersecting pairs (moved %ld vertices, max %.3f cm)\n",
                   rep.initial_pairs, rep.moved, rep.max_displacement);
    if (verbose)
      std::fprintf(stderr, "[rig] bone surface: %ld vertices, %ld triangles, %d shells (%d kept), blur %d\n",
                   long(out.V.rows()), long(out.F.rows()), shells, kept, passes);
    return out;
  }
  throw Error(src_.name + ": could not make a clean bone surface (" + last_error +
              "); try another --flesh-grid");
}

Vec3 predeform_point(const Vec3& x, double w, const Jaw& jaw, double angle_deg) {
  if (w <= 0 || angle_deg == 0) return x;
  const Vec3 r = hinge_apply(x, jaw.pivot, jaw.axis, angle_deg * M_PI / 180.0);
  return x + w * (r - x);
}

}  // namespace facesr
