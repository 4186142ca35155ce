#include "mesh/surface_query.h"

#include <algorithm>
#include <cmath>

#include <embree3/rtcore.h>

#include "mesh/embree_ray.h"

#include "core/error.h"
#include "mesh/closest_point_triangle.h"

namespace facesr {

struct SurfaceQuery::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }
};

namespace {
struct PointQueryData {
  const Points* V;
  const Tris* F;
  Vec3 p;
  SurfaceQuery::Closest best;
};

bool point_query_callback(RTCPointQueryFunctionArguments* args) {
  auto* d = static_cast<PointQueryData*>(args->userPtr);
  const int t = int(args->primID);
  const auto& F = *d->F;
  const auto& V = *d->V;
  Vec3 bary;
  const Vec3 q = closest_point_triangle(d->p, V.row(F(t, 0)), V.row(F(t, 1)), V.row(F(t, 2)), &bary);
  const double dist = (q - d->p).norm();
  if (dist < d->best.dist) {
    d->best = {dist, q, bary, t};
    args->query->radius = float(dist) * (1.0f + 1e-6f) + 1e-7f;  // shrink the search
    return true;
  }
  return false;
}
}  // namespace

SurfaceQuery::SurfaceQuery(const Points& V, const Tris& F) : V_(V), F_(F), impl_(new Impl) {
  require(V.rows() > 0 && F.rows() > 0, "SurfaceQuery: empty mesh");
  // Callers parallelise over queries, hence one thread. The ISA is pinned
  // because the rig builder's results depend on which of Embree's kernels
  // run (measured: the same build gives one rig checksum with isa=sse2 or
  // sse4.2 and another with avx or avx2), and the checksum a shipped model is
  // bound to must not depend on the CPU. SSE2 is on every x86-64 CPU; the
  // ICT rig builds as fast with it (measured, 25 s either way).
  impl_->device = rtcNewDevice("threads=1,isa=sse2");
  require(impl_->device != nullptr, "Embree: cannot create device");
  impl_->scene = rtcNewScene(impl_->device);
  rtcSetSceneBuildQuality(impl_->scene, RTC_BUILD_QUALITY_HIGH);
  RTCGeometry geom = rtcNewGeometry(impl_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), size_t(V.rows())));
  auto* ib = static_cast<unsigned*>(rtcSetNewGeometryBuffer(geom, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                             3 * sizeof(unsigned), size_t(F.rows())));
  for (int i = 0; i < V.rows(); ++i)
    for (int k = 0; k < 3; ++k) vb[3 * i + k] = float(V(i, k));
  for (int f = 0; f < F.rows(); ++f)
    for (int k = 0; k < 3; ++k) ib[3 * f + k] = unsigned(F(f, k));
  rtcCommitGeometry(geom);
  rtcAttachGeometry(impl_->scene, geom);
  rtcReleaseGeometry(geom);
  rtcCommitScene(impl_->scene);
}

SurfaceQuery::~SurfaceQuery() = default;

SurfaceQuery::Closest SurfaceQuery::closest(const Vec3& p, double max_dist) const {
  PointQueryData data{&V_, &F_, p, {}};
  data.best.dist = max_dist;
  RTCPointQuery q = embree_point_query(p, max_dist);
  RTCPointQueryContext ctx;
  rtcInitPointQueryContext(&ctx);
  rtcPointQuery(impl_->scene, &q, &ctx, point_query_callback, &data);
  if (data.best.tri < 0) data.best.dist = std::numeric_limits<double>::infinity();
  return data.best;
}

SurfaceQuery::RayHit SurfaceQuery::first_hit(const Vec3& o, const Vec3& dir, double tmin,
                                             double tmax) const {
  RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  RTCRayHit rh = embree_ray(o, dir, tmin, tmax);
  rtcIntersect1(impl_->scene, &ctx, &rh);
  RayHit out;
  if (rh.hit.geomID != RTC_INVALID_GEOMETRY_ID) {
    out.t = rh.ray.tfar;
    out.tri = int(rh.hit.primID);
    out.bary = Vec3(1.0 - rh.hit.u - rh.hit.v, rh.hit.u, rh.hit.v);
  }
  return out;
}

std::vector<double> SurfaceQuery::all_hits(const Vec3& o, const Vec3& dir, double tmax) const {
  std::vector<double> hits;
  double t = 0;
  const double step = 1e-5 * std::max(1.0, dir.norm());
  for (int guard = 0; guard < 10000; ++guard) {
    const RayHit h = first_hit(o, dir, t, tmax);
    if (h.tri < 0) break;
    hits.push_back(h.t);
    t = h.t + step;
  }
  return hits;
}

}  // namespace facesr
