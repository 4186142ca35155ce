#include "collide/deforming_scene.h"

#include <algorithm>
#include <cmath>

#include <embree3/rtcore.h>

#include "mesh/embree_ray.h"

#include "core/error.h"
#include "mesh/closest_point_triangle.h"

namespace facesr {

struct DeformingScene::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  RTCGeometry geom = nullptr;
  float* vertices = nullptr;
  bool built = false;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {

struct QueryData {
  const std::vector<double>* x;
  const Tris* F;
  Vec3 p;
  DeformingScene::SkipFn skip;
  const void* user;
  DeformingScene::Hit best;
};

Vec3 vertex(const std::vector<double>& x, int v) { return Vec3(x[3 * size_t(v)], x[3 * size_t(v) + 1], x[3 * size_t(v) + 2]); }

bool query_callback(RTCPointQueryFunctionArguments* args) {
  auto* d = static_cast<QueryData*>(args->userPtr);
  const int t = int(args->primID);
  if (d->skip && d->skip(t, d->user)) return false;
  const auto& F = *d->F;
  Vec3 bary;
  const Vec3 q = closest_point_triangle(d->p, vertex(*d->x, F(t, 0)), vertex(*d->x, F(t, 1)), vertex(*d->x, F(t, 2)),
                                        &bary);
  const double dist = (q - d->p).norm();
  if (dist >= d->best.dist) return false;
  d->best = {t, dist, q, bary};
  args->query->radius = float(dist) * (1.0f + 1e-6f) + 1e-7f;
  return true;
}

struct CountData {
  RTCIntersectContext ctx;  // first member: Embree passes this pointer to the filter
  std::vector<std::pair<float, unsigned>> hits;  // (t, triangle)
};

// Records every hit and rejects it, so traversal visits all crossings. Embree
// may report a primitive more than once, so hits are deduplicated by id.
void count_filter(const RTCFilterFunctionNArguments* args) {
  auto* c = reinterpret_cast<CountData*>(args->context);
  for (unsigned i = 0; i < args->N; ++i)
    if (args->valid[i] == -1) {
      // During the filter call the ray's tfar holds the candidate hit's distance.
      c->hits.emplace_back(RTCRayN_tfar(args->ray, args->N, i), RTCHitN_primID(args->hit, args->N, i));
      args->valid[i] = 0;
    }
}

}  // namespace

DeformingScene::DeformingScene(const Tris& F, int num_vertices) : F_(F), nv_(num_vertices), impl_(new Impl) {
  require(F.rows() > 0 && num_vertices > 0, "DeformingScene: empty mesh");
  require(F.minCoeff() >= 0 && F.maxCoeff() < num_vertices, "DeformingScene: triangle index out of range");
  impl_->device = rtcNewDevice("threads=1");  // the solver parallelises over queries
  require(impl_->device != nullptr, "Embree: cannot create device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneFlags(impl_->scene, RTC_SCENE_FLAG_DYNAMIC);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_LOW);
  impl_->geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryBuildQuality(impl_->geom, RTC_BUILD_QUALITY_REFIT);
  impl_->vertices = static_cast<float*>(rtcSetNewGeometryBuffer(impl_->geom, RTC_BUFFER_TYPE_VERTEX, 0,
                                                                RTC_FORMAT_FLOAT3, 3 * sizeof(float), size_t(nv_)));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(impl_->geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), size_t(F.rows())));
  for (long f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ib[3 * f + k] = unsigned(F(f, k));
  rtcSetGeometryIntersectFilterFunction(impl_->geom, count_filter);
  rtcAttachGeometry(impl_->scene, impl_->geom);
  rtcReleaseGeometry(impl_->geom);  // the scene holds it
}

DeformingScene::~DeformingScene() = default;

void DeformingScene::update(const std::vector<double>& x) {
  require(x.size() == 3 * size_t(nv_), "DeformingScene::update: expected " + std::to_string(3 * nv_) +
                                           " coordinates, got " + std::to_string(x.size()));
  x_ = x;
  for (size_t i = 0; i < x.size(); ++i) impl_->vertices[i] = float(x[i]);
  if (impl_->built) rtcUpdateGeometryBuffer(impl_->geom, RTC_BUFFER_TYPE_VERTEX, 0);
  rtcCommitGeometry(impl_->geom);
  rtcCommitScene(impl_->scene);
  impl_->built = true;
}

DeformingScene::Hit DeformingScene::closest(const Vec3& p, double max_dist, SkipFn skip, const void* user) const {
  require(impl_->built, "DeformingScene: query before update()");
  QueryData d{&x_, &F_, p, skip, user, {}};
  d.best.dist = max_dist;
  RTCPointQuery q = embree_point_query(p, max_dist);
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &q, &ctx, query_callback, &d);
  if (d.best.tri < 0) d.best.dist = std::numeric_limits<double>::infinity();
  return d.best;
}

std::vector<std::pair<double, int>> DeformingScene::hits(const Vec3& o, const Vec3& dir, double tmax) const {
  require(impl_->built, "DeformingScene: query before update()");
  CountData c;
  rtcInitIntersectContext(&c.ctx);
  RTCRayHit rh = embree_ray(o, dir, 0, tmax);
  rtcIntersect1(impl_->scene, &c.ctx, &rh);
  std::sort(c.hits.begin(), c.hits.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  std::vector<std::pair<double, int>> out;
  for (size_t i = 0; i < c.hits.size(); ++i)
    if (i == 0 || c.hits[i].second != c.hits[i - 1].second) out.emplace_back(c.hits[i].first, int(c.hits[i].second));
  std::sort(out.begin(), out.end());
  return out;
}

int DeformingScene::crossings(const Vec3& o, const Vec3& dir, double tmax) const {
  return int(hits(o, dir, tmax).size());
}

Vec3 DeformingScene::face_normal(int t) const {
  const Vec3 a = vertex(x_, F_(t, 0)), b = vertex(x_, F_(t, 1)), c = vertex(x_, F_(t, 2));
  const Vec3 n = (b - a).cross(c - a);
  const double len = n.norm();
  return len > 0 ? Vec3(n / len) : Vec3::Zero();
}

}  // namespace facesr
