#include "rig/rig_build.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <set>

#include "core/binary_io.h"
#include "core/error.h"
#include "core/progress.h"
#include "mesh/surface_query.h"
#include "mesh/tet_locator.h"
#include "mesh/tetrahedralize.h"
#include "rig/flesh.h"
#include "rig/ict_head.h"
#include "rig/jaw_fit.h"
#include "rig/lattice.h"
#include "rig/muscles.h"

namespace facesr {

Jaw fit_jaw(const HeadSource& src) {
  Jaw jaw;
  require(src.teeth_lower.V.rows() >= 3, src.name + ": no lower teeth to fit the jaw motion to");
  for (const auto& [name, teeth] : src.jaw_shape_lower_teeth) {
    JawShape s;
    s.name = name;
    fit_rigid(src.teeth_lower.V, teeth, s.R, s.t, &s.fit_rms_cm);
    jaw.shapes.push_back(s);
  }
  const auto open = std::find_if(jaw.shapes.begin(), jaw.shapes.end(), [](const JawShape& s) { return s.name == "jawOpen"; });
  require(open != jaw.shapes.end(), src.name + ": no jawOpen blendshape, cannot find the jaw hinge");
  double angle = 0;
  hinge_from_rigid(open->R, open->t, jaw.pivot, jaw.axis, angle);
  require(angle * 180.0 / M_PI > 1.0, src.name + ": jawOpen rotates the lower teeth by " +
                                          std::to_string(angle * 180.0 / M_PI) +
                                          " degrees; a jaw hinge needs at least 1");
  // The pivot's place along the axis does not change a hinge, but it is the
  // point the other jaw shapes' shifts are measured at when they combine
  // with jawOpen (jaw_transform), so it must lie by the jaw. The minimum-norm
  // point (nearest the origin) does for heads modelled around the origin,
  // and rigs built before keep their bytes; a head placed far from the
  // origin gets the point on the axis beside its lower teeth.
  const Vec3 teeth_centre = src.teeth_lower.V.colwise().mean().transpose();
  const Vec3 beside = nearest_on_axis(jaw.pivot, jaw.axis, teeth_centre);
  if ((beside - jaw.pivot).norm() > kJawPivotSlackCm) jaw.pivot = beside;
  jaw.open_angle_deg = angle * 180.0 / M_PI;
  const auto& teeth = std::find_if(src.jaw_shape_lower_teeth.begin(), src.jaw_shape_lower_teeth.end(),
                                   [](const auto& p) { return p.first == "jawOpen"; })->second;
  for (int i = 0; i < src.teeth_lower.V.rows(); ++i) {
    const Vec3 h = hinge_apply(src.teeth_lower.V.row(i), jaw.pivot, jaw.axis, angle);
    jaw.hinge_max_error_cm = std::max(jaw.hinge_max_error_cm, (h - Vec3(teeth.row(i))).norm());
  }
  return jaw;
}

namespace {

// One point strictly inside each closed shell: from a triangle's centroid,
// step inward half way to the opposite wall.
std::vector<Vec3> hole_points(const TriMesh& shells) {
  int nc = 0;
  const auto comp = face_components(shells.F, shells.V.rows(), nc);
  SurfaceQuery q(shells.V, shells.F);
  std::vector<Vec3> holes;
  std::vector<bool> done(nc, false);
  for (int f = 0; f < shells.F.rows(); ++f) {
    if (done[comp[f]]) continue;
    const Vec3 a = shells.V.row(shells.F(f, 0)), b = shells.V.row(shells.F(f, 1)), c = shells.V.row(shells.F(f, 2));
    const Vec3 n = (b - a).cross(c - a);
    if (n.norm() < 1e-8) continue;
    const Vec3 in = -n.normalized();
    const Vec3 o = (a + b + c) / 3.0;
    const auto hit = q.first_hit(o, in, 1e-4, 1e3);
    if (hit.tri < 0 || hit.t < 1e-3) continue;
    holes.push_back(o + 0.5 * hit.t * in);
    done[comp[f]] = true;
  }
  return holes;
}

std::vector<double> vertex_areas(const Points& V, const Tris& F) {
  std::vector<double> A(V.rows(), 0.0);
  for (int f = 0; f < F.rows(); ++f) {
    const Vec3 a = V.row(F(f, 0)), b = V.row(F(f, 1)), c = V.row(F(f, 2));
    const double area = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) A[F(f, k)] += area / 3.0;
  }
  return A;
}

void embed(const TetMesh& mesh, const Points& P, Embedding& e, double search) {
  TetLocator loc(mesh);
  const int n = int(P.rows());
  e.tet.assign(n, -1);
  e.weights.assign(size_t(n) * 4, 0.0f);
  e.outside.assign(n, 0);
#pragma omp parallel for schedule(dynamic, 256)
  for (int i = 0; i < n; ++i) {
    auto r = loc.locate(P.row(i).transpose(), 0);
    if (r.tet < 0 || !r.inside) {
      auto r2 = loc.locate(P.row(i).transpose(), search);
      if (r2.tet >= 0 && (r.tet < 0 || r2.inside || r2.bary.minCoeff() > r.bary.minCoeff())) r = r2;
    }
    require(r.tet >= 0, "embedding: no tet near surface vertex " + std::to_string(i));
    e.tet[i] = r.tet;
    e.outside[i] = r.inside ? 0 : 1;
    for (int k = 0; k < 4; ++k) e.weights[size_t(i) * 4 + k] = float(r.bary[k]);
  }
}

}  // namespace

void lip_vertices(const Rig& rig, std::vector<int>& upper, std::vector<int>& lower) {
  upper.clear();
  lower.clear();
  auto lm = [&](const char* name) -> Vec3 {
    for (size_t i = 0; i < rig.landmark_names.size(); ++i)
      if (rig.landmark_names[i] == name) return rig.surface.row(rig.landmark_vertex[i]).transpose();
    throw Error(std::string("rig has no landmark '") + name + "'");
  };
  const Vec3 cl = lm("mouth_corner_L"), cr = lm("mouth_corner_R"), top = lm("upper_lip_top"), bot = lm("lower_lip_bottom");
  const double zmin = std::min(cl.z(), cr.z()) - 1.0;
  // The lips proper: the commissures (within 15% of the mouth width of a
  // corner) join both lips and are not separable; weights near 0.5 are
  // neither lip.
  const double margin = 0.15 * (cl.x() - cr.x());
  for (int v = 0; v < rig.surface.rows(); ++v) {
    const Vec3 p = rig.surface.row(v);
    if (p.x() < cr.x() + margin || p.x() > cl.x() - margin || p.y() < bot.y() - 0.3 || p.y() > top.y() + 0.3 ||
        p.z() < zmin)
      continue;
    const float w = rig.predeform.surface_jaw_weight[v];
    if (w < 0.3f) upper.push_back(v);
    else if (w > 0.7f) lower.push_back(v);
  }
}

Rig build_rig(const RigBuildOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  StageLog log(opt.verbose);
  require(opt.lr_cell > 0.1 && opt.lr_cell < 5, "lr cell size must be in (0.1, 5) cm");
  require(opt.flesh_grid_h > 0.02 && opt.flesh_grid_h < 1, "flesh grid spacing must be in (0.02, 1) cm");

  log.begin("load head '" + opt.source + "'");
  HeadSource src = opt.source == "procedural" ? make_procedural_head(opt.procedural)
                                               : load_ict_head(opt.source, opt.verbose);
  log.end(std::to_string(src.skin.V.rows()) + " skin vertices, " + std::to_string(src.blendshape_names.size()) +
          " blendshapes");
  std::string muscle_text = default_muscle_spec(), muscle_name = "built-in muscles.json";
  if (!opt.muscles_path.empty()) {
    const auto bytes = read_file_bytes(opt.muscles_path);
    muscle_text.assign(bytes.begin(), bytes.end());
    muscle_name = opt.muscles_path;
  }

  Rig rig;
  rig.name = src.name;
  rig.source = opt.source;

  log.begin("fit jaw from lower teeth");
  rig.jaw = fit_jaw(src);
  log.end("open angle " + std::to_string(rig.jaw.open_angle_deg) + " deg, hinge error " +
          std::to_string(rig.jaw.hinge_max_error_cm) + " cm");

  log.begin("flesh domain (signed distance, soft-tissue thickness)");
  FleshDomain flesh(src, rig.jaw, opt.flesh_grid_h, opt.verbose);
  log.end();

  log.begin("bone surface");
  const TriMesh bone = flesh.bone_surface(opt.bone_edge, opt.verbose);
  log.end();

  // HR conforming mesh: skin shell outside, bone shells inside.
  log.begin("HR tetrahedralisation (TetGen)");
  const long ns = src.skin.V.rows();
  TriMesh plc;
  plc.V.resize(ns + bone.V.rows(), 3);
  plc.V << src.skin.V, bone.V;
  plc.F.resize(src.skin.F.rows() + bone.F.rows(), 3);
  plc.F << src.skin.F, (bone.F.array() + int32_t(ns)).matrix();
  TetgenOptions tg;
  tg.max_volume = opt.hr_max_volume;
  tg.radius_edge = opt.hr_radius_edge;
  rig.hr.mesh = tetrahedralize(plc, hole_points(bone), tg);
  log.end(std::to_string(rig.hr.mesh.T.rows()) + " tets, " + std::to_string(rig.hr.mesh.X.rows()) + " nodes");

  // Face surface and its blendshapes.
  std::vector<int> surf_of_skin(ns, -1);
  const int nsv = int(src.face_vertices.size());
  rig.surface.resize(nsv, 3);
  for (int i = 0; i < nsv; ++i) {
    surf_of_skin[src.face_vertices[i]] = i;
    rig.surface.row(i) = src.skin.V.row(src.face_vertices[i]);
    rig.surface_source_vertex.push_back(src.face_vertices[i]);
  }
  std::vector<Vec3i> tris;
  for (int f = 0; f < src.skin.F.rows(); ++f) {
    const int a = surf_of_skin[src.skin.F(f, 0)], b = surf_of_skin[src.skin.F(f, 1)], c = surf_of_skin[src.skin.F(f, 2)];
    if (a >= 0 && b >= 0 && c >= 0) tris.emplace_back(a, b, c);
  }
  rig.surface_tris.resize(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) rig.surface_tris.row(long(t)) = tris[t].cast<int32_t>().transpose();
  rig.blendshape_names = src.blendshape_names;
  for (const auto& d : src.blendshape_deltas)
    for (int i = 0; i < nsv; ++i)
      for (int k = 0; k < 3; ++k) rig.blendshape_deltas.push_back(float(d(src.face_vertices[i], k)));
  for (const auto& [name, v] : src.landmarks)
    if (surf_of_skin[v] >= 0) {
      rig.landmark_names.push_back(name);
      rig.landmark_vertex.push_back(surf_of_skin[v]);
    }
  rig.teeth_upper = src.teeth_upper;
  rig.teeth_lower = src.teeth_lower;

  log.begin("HR attachments and embedding");
  {
    std::set<int> cap;
    for (int f = 0; f < src.skin.F.rows(); ++f) {
      bool touches = false;
      for (int k = 0; k < 3; ++k) touches |= src.region[src.skin.F(f, k)] == SkinRegion::NeckCap;
      if (touches)
        for (int k = 0; k < 3; ++k) cap.insert(src.skin.F(f, k));
    }
    for (int v : cap) {
      rig.hr.dirichlet.push_back(v);
      rig.hr.dirichlet_bone.push_back(0);
    }
    for (long v = ns; v < ns + bone.V.rows(); ++v) {
      rig.hr.dirichlet.push_back(int32_t(v));
      rig.hr.dirichlet_bone.push_back(flesh.jaw_weight(rig.hr.mesh.X.row(v)) > 0.5 ? 1 : 0);
    }
    embed(rig.hr.mesh, rig.surface, rig.hr.surface, 1.0);
  }
  log.end(std::to_string(rig.hr.dirichlet.size()) + " Dirichlet nodes");

  // Jaw weights on the face surface; lip-separating predeformation.
  rig.predeform.surface_jaw_weight.resize(nsv);
  for (int i = 0; i < nsv; ++i) rig.predeform.surface_jaw_weight[i] = float(flesh.skin_jaw_weight()[src.face_vertices[i]]);

  log.begin("HR node jaw weights");
  const int nh = int(rig.hr.mesh.X.rows());
  std::vector<double> hr_w(nh);
#pragma omp parallel for schedule(dynamic, 1024)
  for (int v = 0; v < nh; ++v) hr_w[v] = flesh.jaw_weight(rig.hr.mesh.X.row(v));
  log.end();

  // Which HR tets are face flesh (the lattice drops neck and back of head).
  std::vector<uint8_t> near_face(ns, 0);
  for (long v = 0; v < ns; ++v) near_face[v] = src.region[v] == SkinRegion::Face;
  {
    std::vector<Vec3> face_pts;
    for (int v : src.face_vertices) face_pts.push_back(src.skin.V.row(v));
    for (long v = 0; v < ns; ++v) {
      if (src.region[v] != SkinRegion::Mouth && src.region[v] != SkinRegion::EyeSocket) continue;
      const Vec3 p = src.skin.V.row(v);
      for (const auto& q : face_pts)
        if ((p - q).squaredNorm() < 2.0 * 2.0) {
          near_face[v] = 1;
          break;
        }
    }
  }
  std::vector<uint8_t> face_tet(rig.hr.mesh.T.rows(), 0);
#pragma omp parallel for schedule(dynamic, 1024)
  for (long t = 0; t < rig.hr.mesh.T.rows(); ++t) {
    Vec3 c = Vec3::Zero();
    for (int k = 0; k < 4; ++k) c += rig.hr.mesh.X.row(rig.hr.mesh.T(t, k)).transpose() / 4.0;
    face_tet[t] = near_face[flesh.nearest_skin_vertex(c)];
  }

  std::vector<int> upper, lower;
  rig.predeform.surface_predeformed = rig.surface;
  lip_vertices(rig, upper, lower);
  double cell = opt.lr_cell;
  std::vector<long> cells;
  for (int attempt = 0; attempt < 12; ++attempt) {
    log.begin("LR lattice, cell " + std::to_string(cell) + " cm");
    // Smallest hinge angle (0.5° steps) at which no lattice tet holds both lips.
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (int v = 0; v < nh; ++v) {
      const Vec3 p = predeform_point(rig.hr.mesh.X.row(v), hr_w[v], rig.jaw, opt.max_predeform_deg);
      lo = lo.cwiseMin(p).cwiseMin(rig.hr.mesh.X.row(v).transpose());
      hi = hi.cwiseMax(p).cwiseMax(rig.hr.mesh.X.row(v).transpose());
    }
    rig.lattice.cell = cell;
    rig.lattice.origin = lo - Vec3::Constant(cell);
    for (int a = 0; a < 3; ++a) rig.lattice.dims[a] = int(std::ceil((hi[a] - lo[a]) / cell)) + 2;
    double angle = -1;
    for (double a = 0; a <= opt.max_predeform_deg + 1e-9; a += 0.5) {
      std::set<std::pair<long, int>> up;
      for (int v : upper) {
        long c;
        int k;
        lattice_locate(rig.lattice, predeform_point(rig.surface.row(v), rig.predeform.surface_jaw_weight[v], rig.jaw, a), c, k);
        up.emplace(c, k);
      }
      bool clash = false;
      for (int v : lower) {
        long c;
        int k;
        lattice_locate(rig.lattice, predeform_point(rig.surface.row(v), rig.predeform.surface_jaw_weight[v], rig.jaw, a), c, k);
        if (up.count({c, k})) {
          clash = true;
          break;
        }
      }
      if (!clash) {
        angle = a;
        break;
      }
    }
    require(angle >= 0, "cannot separate the lips in the lattice within " + std::to_string(opt.max_predeform_deg) +
                            " degrees of jaw rotation; use a smaller --lr-cell");
    rig.predeform.angle_deg = angle;
    for (int i = 0; i < nsv; ++i)
      rig.predeform.surface_predeformed.row(i) =
          predeform_point(rig.surface.row(i), rig.predeform.surface_jaw_weight[i], rig.jaw, angle).transpose();
    std::set<long> cellset;
    auto mark = [&](const Vec3& p) {
      long c;
      int k;
      lattice_locate(rig.lattice, p, c, k);
      cellset.insert(c);
    };
    for (long t = 0; t < rig.hr.mesh.T.rows(); ++t) {
      if (!face_tet[t]) continue;
      Vec3 c = Vec3::Zero();
      for (int k = 0; k < 4; ++k) {
        const int v = rig.hr.mesh.T(t, k);
        const Vec3 p = predeform_point(rig.hr.mesh.X.row(v), hr_w[v], rig.jaw, angle);
        c += p / 4.0;
        mark(p);
      }
      mark(c);
    }
    for (int i = 0; i < nsv; ++i) mark(rig.predeform.surface_predeformed.row(i));
    cells.assign(cellset.begin(), cellset.end());
    std::vector<long> first;
    rig.lr.mesh = lattice_mesh(rig.lattice, cells, first);
    const double ratio = double(rig.hr.mesh.T.rows()) / double(rig.lr.mesh.T.rows());
    log.end(std::to_string(rig.lr.mesh.T.rows()) + " tets, HR/LR " + std::to_string(ratio) + ", lip predeform " +
            std::to_string(angle) + " deg");
    if (ratio >= opt.min_hr_over_lr) break;
    cell *= 1.1;
  }

  auto to_rest = [&](const Vec3& p) {
    return predeform_point(p, flesh.jaw_weight(p), rig.jaw, -rig.predeform.angle_deg);
  };

  log.begin("LR embedding and attachments");
  embed(rig.lr.mesh, rig.predeform.surface_predeformed, rig.lr.surface, 2.0 * cell);
  for (int v = 0; v < rig.lr.mesh.X.rows(); ++v) {
    const Vec3 r = to_rest(rig.lr.mesh.X.row(v));
    if (flesh.sd(r) < 0 && flesh.bone(r) < 0) {
      rig.lr.dirichlet.push_back(v);
      rig.lr.dirichlet_bone.push_back(flesh.jaw_weight(r) > 0.5 ? 1 : 0);
    }
  }
  log.end(std::to_string(rig.lr.dirichlet.size()) + " Dirichlet nodes");

  log.begin("muscles");
  const MuscleSet ms = build_muscles(muscle_text, muscle_name, src, flesh.skin_query());
  rig.muscles = ms.muscles;
  rig.activation = ms.activation;
  rasterize_muscles(rig.muscles, 5, [](const Vec3& p) { return p; }, [](const Vec3&) { return true; }, rig.hr);
  rasterize_muscles(rig.muscles, 20, to_rest, [&](const Vec3& p) { return flesh.in_flesh(p); }, rig.lr);
  log.end(std::to_string(rig.muscles.size()) + " muscles");

  // Track points: every face vertex on HR; one per half-cell bin on LR, each
  // carrying the skin area it stands for (track stiffness is per area).
  const auto area = vertex_areas(rig.surface, rig.surface_tris);
  for (int i = 0; i < nsv; ++i) {
    rig.hr.tracks.push_back(i);
    rig.hr.track_area.push_back(float(area[i]));
  }
  {
    std::map<std::tuple<int, int, int>, std::vector<int>> bins;
    const double b = 0.5 * cell;
    for (int i = 0; i < nsv; ++i) {
      const Vec3 p = rig.surface.row(i);
      bins[{int(std::floor(p.x() / b)), int(std::floor(p.y() / b)), int(std::floor(p.z() / b))}].push_back(i);
    }
    for (const auto& [key, vs] : bins) {
      Vec3 c = Vec3::Zero();
      double A = 0;
      for (int v : vs) c += rig.surface.row(v).transpose(), A += area[v];
      c /= double(vs.size());
      int best = vs[0];
      for (int v : vs)
        if ((rig.surface.row(v).transpose() - c).squaredNorm() < (rig.surface.row(best).transpose() - c).squaredNorm()) best = v;
      rig.lr.tracks.push_back(best);
      rig.lr.track_area.push_back(float(A));
    }
  }
  rig.build_seconds = seconds_since(t0);
  return rig;
}

}  // namespace facesr
