#include "collide/mouth_collider.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "collide/boundary_faces.h"
#include "core/error.h"

namespace facesr {

// A rigid obstacle: its scene in its own rest frame; queries move the point
// into that frame (the lower teeth follow the jaw).
struct MouthCollider::Teeth {
  std::unique_ptr<DeformingScene> scene;
  bool closed = false;
};

namespace {

Vec3 node_pos(const std::vector<double>& x, int n) {
  return Vec3(x[3 * size_t(n)], x[3 * size_t(n) + 1], x[3 * size_t(n) + 2]);
}

bool watertight(const Tris& F) {
  std::map<std::pair<int, int>, int> edges;
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) {
      const int a = F(f, k), b = F(f, (k + 1) % 3);
      ++edges[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, n] : edges)
    if (n != 2) return false;
  return true;
}

std::unique_ptr<MouthCollider::Teeth> make_teeth(const TriMesh& m) {
  if (m.V.rows() == 0 || m.F.rows() == 0) return nullptr;
  auto t = std::make_unique<MouthCollider::Teeth>();
  t->scene = std::make_unique<DeformingScene>(m.F, int(m.V.rows()));
  std::vector<double> x(3 * size_t(m.V.rows()));
  for (long v = 0; v < m.V.rows(); ++v)
    for (int k = 0; k < 3; ++k) x[3 * v + k] = m.V(v, k);
  t->scene->update(x);
  t->closed = watertight(m.F);
  return t;
}

bool skip_own(int tri, const void* user) {
  const auto& own = *static_cast<const std::vector<int>*>(user);
  return std::binary_search(own.begin(), own.end(), tri);
}

// A direction unlikely to graze mesh edges or vertices exactly.
const Vec3 kParityDir = Vec3(0.1234, 0.3571, 0.9259).normalized();

// Signed penetration of p into a rigid obstacle given in its own frame (p
// already mapped there), counting points within `margin` outside it, and the
// contact plane in that frame.
bool teeth_contact(const MouthCollider::Teeth& t, const Vec3& p, double max_depth, double margin, Vec3& q, Vec3& n,
                   double& depth) {
  const DeformingScene::Hit h = t.scene->closest(p, max_depth);
  if (h.tri < 0) return false;
  const Vec3 nt = t.scene->face_normal(h.tri);
  const bool inside = t.closed ? (t.scene->crossings(p, kParityDir) % 2 == 1) : (h.point - p).dot(nt) > 0;
  if (!inside && h.dist >= margin) return false;
  q = h.point;
  // The direction to the closest point is the most reliable normal (exact at
  // edges and corners); the face normal covers points on the surface.
  n = h.dist > 1e-9 ? Vec3((inside ? 1.0 : -1.0) * (h.point - p) / h.dist) : nt;
  depth = inside ? h.dist : -h.dist;
  return true;
}

// Whether the first surface (outside the node's own neighbourhood) met along
// p + t·dir is entered from its back, i.e. p lies inside the body.
bool ray_exits_body(const DeformingScene& skin, const Vec3& p, const Vec3& dir, const std::vector<int>& own) {
  for (const auto& [t, tri] : skin.hits(p, dir))
    if (!std::binary_search(own.begin(), own.end(), tri)) return skin.face_normal(tri).dot(dir) > 0;
  return false;
}

}  // namespace

MouthCollider::MouthCollider(const Rig& rig, const SimModel& model, const CollisionOptions& opt) : opt_(opt) {
  require(model.res == Resolution::High, "collisions: the mouth collider works on the HR simulation model");
  require(opt.stiffness > 0 && opt.max_depth_cm > 0 && opt.region_scale > 0 && opt.exclude_rings >= 0,
          "collisions: stiffness, max depth and region scale must be positive");
  num_nodes_ = model.num_nodes;
  // Mouth centre and width from the outer lip contour landmarks.
  Vec3 centre = Vec3::Zero(), corner_l = Vec3::Zero(), corner_r = Vec3::Zero();
  int ring = 0;
  for (size_t i = 0; i < rig.landmark_names.size(); ++i) {
    const Vec3 p = rig.surface.row(rig.landmark_vertex[i]);
    const std::string& name = rig.landmark_names[i];
    if (name.rfind("mouth_ring_", 0) == 0) centre += p, ++ring;
    if (name == "mouth_corner_L") corner_l = p;
    if (name == "mouth_corner_R") corner_r = p;
  }
  require(ring > 0, "collisions: rig '" + rig.name + "' has no mouth_ring landmarks");
  centre /= ring;
  info_.mouth_width_cm = (corner_l - corner_r).norm();
  require(info_.mouth_width_cm > 0, "collisions: rig '" + rig.name + "' has no mouth corner landmarks");
  const double radius = opt.region_scale * info_.mouth_width_cm;

  const Tris B = boundary_faces(rig.hr.mesh);
  std::vector<int> local(model.num_nodes, -1);
  std::vector<Vec3i> tris;
  auto in_region = [&](int n) { return (node_pos(model.rest, n) - centre).norm() < radius; };
  for (long f = 0; f < B.rows(); ++f)
    if (in_region(B(f, 0)) && in_region(B(f, 1)) && in_region(B(f, 2))) {
      tris.emplace_back(B(f, 0), B(f, 1), B(f, 2));
      for (int k = 0; k < 3; ++k)
        if (local[B(f, k)] < 0) {
          local[B(f, k)] = int(region_.size());
          region_.push_back(B(f, k));
        }
    }
  require(!tris.empty(), "collisions: no HR skin within " + std::to_string(radius) + " cm of the mouth");
  Tris F(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) F.row(long(t)) = tris[t].transpose();
  info_.region_nodes = int(region_.size());
  info_.region_triangles = int(F.rows());

  // Per-node area, incident triangles and adjacency.
  const size_t nr = region_.size();
  std::vector<double> area(nr, 0.0);
  node_tris_.assign(nr, {});
  std::vector<std::vector<int>> adj(nr);
  for (long t = 0; t < F.rows(); ++t) {
    const Vec3 a = node_pos(model.rest, F(t, 0)), b = node_pos(model.rest, F(t, 1)), c = node_pos(model.rest, F(t, 2));
    const double A = 0.5 * (b - a).cross(c - a).norm();
    for (int k = 0; k < 3; ++k) {
      const int i = local[F(t, k)], j = local[F(t, (k + 1) % 3)];
      area[i] += A / 3;
      node_tris_[i].push_back(int(t));
      adj[i].push_back(j);
      adj[j].push_back(i);
    }
  }
  k_.resize(nr);
  for (size_t i = 0; i < nr; ++i) k_[i] = opt.stiffness * area[i];
  // Own neighbourhood: triangles touching nodes within exclude_rings rings.
  own_.assign(nr, {});
  std::vector<int> mark(nr, -1);
  for (size_t i = 0; i < nr; ++i) {
    std::vector<int> frontier{int(i)}, seen{int(i)};
    mark[i] = int(i);
    for (int r = 0; r < opt.exclude_rings; ++r) {
      std::vector<int> next;
      for (int u : frontier)
        for (int v : adj[u])
          if (mark[v] != int(i)) {
            mark[v] = int(i);
            next.push_back(v);
            seen.push_back(v);
          }
      frontier.swap(next);
    }
    for (int u : seen) own_[i].insert(own_[i].end(), node_tris_[u].begin(), node_tris_[u].end());
    std::sort(own_[i].begin(), own_[i].end());
    own_[i].erase(std::unique(own_[i].begin(), own_[i].end()), own_[i].end());
  }
  skin_ = std::make_unique<DeformingScene>(F, model.num_nodes);
  if (opt.teeth) {
    upper_ = make_teeth(rig.teeth_upper);
    lower_ = make_teeth(rig.teeth_lower);
    info_.teeth_closed = (!upper_ || upper_->closed) && (!lower_ || lower_->closed);
  }
  region_free_.assign(nr, 1);
  for (size_t i = 0; i < nr; ++i)
    if (model.node_bone[region_[i]]) region_free_[i] = 0;
  // Skin that already lies behind an obstacle at rest (e.g. where the source
  // mesh's lips overlap) would be pushed out at every frame; it is left alone.
  FrameInputs rest_in;
  std::vector<ContactPlane> rest_contacts;
  find(model.rest, rest_in, rest_contacts);
  for (const auto& c : rest_contacts)
    if (c.penetration > 0) {
      region_free_[local[c.node]] = 0;
      ++info_.rest_excluded;
    }
}

MouthCollider::~MouthCollider() = default;

void MouthCollider::detect(const std::vector<double>& x, const FrameInputs& in, std::vector<ContactPlane>& out) {
  find(x, in, out);
}

void MouthCollider::find(const std::vector<double>& x, const FrameInputs& in, std::vector<ContactPlane>& out) const {
  require(x.size() == 3 * size_t(num_nodes_), "collisions: expected " + std::to_string(3 * num_nodes_) +
                                                  " node coordinates, got " + std::to_string(x.size()));
  out.clear();
  if (opt_.self) skin_->update(x);
  const size_t nr = region_.size();
  std::vector<ContactPlane> slot(nr);
  const Mat3 Rt = in.jaw_R.transpose();
#pragma omp parallel for schedule(dynamic, 64)
  for (long i = 0; i < long(nr); ++i) {
    if (!region_free_[i]) continue;
    const Vec3 p = node_pos(x, region_[i]);
    double best = -opt_.margin_cm;
    ContactPlane c;
    if (opt_.self) {
      const DeformingScene::Hit h = skin_->closest(p, opt_.max_depth_cm, skip_own, &own_[i]);
      if (h.tri >= 0) {
        Vec3 np = Vec3::Zero();
        for (int t : node_tris_[i]) np += skin_->face_normal(t);
        np.normalize();
        const Vec3 nt = skin_->face_normal(h.tri);
        double d = (h.point - p).dot(nt);
        // Behind the other skin and facing it. Being behind the nearest
        // surface is not enough (the inner lining of a lip lies behind that
        // lip's own outer skin): the node is inside the body only if a ray
        // along its own outward normal leaves the body, i.e. first meets a
        // surface from the back.
        if (d > 0 && !(np.dot(nt) < 0 && ray_exits_body(*skin_, p, np, own_[i]))) d = -1e300;
        // Both skins are pushed, each to the plane half way between them, so
        // that together they close the gap once instead of overshooting twice.
        if (d > best && np.dot(nt) < 0) {
          best = d;
          c = {region_[i], p + 0.5 * d * nt, nt, k_[i], kLipSelf, d};
        }
      }
    }
    Vec3 q, n;
    double d;
    if (upper_ && teeth_contact(*upper_, p, opt_.max_depth_cm, opt_.margin_cm, q, n, d) && d > best) {
      best = d;
      c = {region_[i], q, n, k_[i], kUpperTeeth, d};
    }
    if (lower_ && teeth_contact(*lower_, Rt * (p - in.jaw_t), opt_.max_depth_cm, opt_.margin_cm, q, n, d) &&
        d > best) {
      best = d;
      c = {region_[i], in.jaw_R * q + in.jaw_t, in.jaw_R * n, k_[i], kLowerTeeth, d};
    }
    if (c.node >= 0) slot[i] = c;
  }
  for (const auto& c : slot)
    if (c.node >= 0) out.push_back(c);
}

}  // namespace facesr
