#include "render/mesh_raster.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "core/error.h"

namespace facesr {
namespace {

constexpr double kAmbient = 0.25;

Vec3 point(const float* xyz, int i) { return Vec3(xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]); }

// Toward the light: from the viewer's upper left, as in the rig preview.
const Vec3& light_direction() {
  static const Vec3 l = Vec3(-0.3, 0.5, 1.0).normalized();
  return l;
}

}  // namespace

FrontView frame_front_view(const Vec3& lo, const Vec3& hi, int x0, int y0, int width, int height, double fill) {
  FrontView v;
  v.centre = 0.5 * (lo + hi);
  v.x0 = x0;
  v.y0 = y0;
  v.width = std::max(1, width);
  v.height = std::max(1, height);
  const double ex = std::max(hi.x() - lo.x(), 1e-9), ey = std::max(hi.y() - lo.y(), 1e-9);
  v.px_per_cm = fill * std::min(v.width / ex, v.height / ey);
  return v;
}

void extend_box(const float* xyz, size_t n, Vec3& lo, Vec3& hi) {
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], double(xyz[3 * i + k]));
      hi[k] = std::max(hi[k], double(xyz[3 * i + k]));
    }
}

std::vector<Vec3> vertex_normals_xyz(const float* xyz, int num_vertices, const Tris& tris) {
  std::vector<Vec3> n(num_vertices, Vec3::Zero());
  for (int t = 0; t < tris.rows(); ++t) {
    const int a = tris(t, 0), b = tris(t, 1), c = tris(t, 2);
    // The cross product's length is twice the area: area weighting for free.
    const Vec3 fn = (point(xyz, b) - point(xyz, a)).cross(point(xyz, c) - point(xyz, a));
    n[a] += fn;
    n[b] += fn;
    n[c] += fn;
  }
  for (Vec3& v : n) {
    const double len = v.norm();
    v = len > 1e-20 ? Vec3(v / len) : Vec3::UnitZ();
  }
  return n;
}

void rasterize_mesh(Image& img, const FrontView& view, const float* xyz, int num_vertices, const Tris& tris,
                    const std::vector<Rgb>& vertex_colour, Rgb colour) {
  require(vertex_colour.empty() || int(vertex_colour.size()) == num_vertices,
          "rasterize_mesh: " + std::to_string(vertex_colour.size()) + " vertex colours for " +
              std::to_string(num_vertices) + " vertices");
  require(tris.size() == 0 || (tris.minCoeff() >= 0 && tris.maxCoeff() < num_vertices),
          "rasterize_mesh: triangle index out of range (" + std::to_string(num_vertices) + " vertices)");
  const std::vector<Vec3> normals = vertex_normals_xyz(xyz, num_vertices, tris);
  std::vector<Vec3> screen(num_vertices);
  for (int i = 0; i < num_vertices; ++i) screen[i] = view.project(point(xyz, i));
  auto rgb = [&](int v) {
    const Rgb c = vertex_colour.empty() ? colour : vertex_colour[v];
    return Vec3(c.r, c.g, c.b);
  };

  // Clip to the image as well as the view, so a view hanging off the image is safe.
  const int xa = std::max(view.x0, 0), ya = std::max(view.y0, 0);
  const int xb = std::min(view.x0 + view.width, img.width()), yb = std::min(view.y0 + view.height, img.height());
  if (xa >= xb || ya >= yb) return;
  const int zw = xb - xa;
  std::vector<double> zbuf(size_t(zw) * (yb - ya), std::numeric_limits<double>::infinity());
  const Vec3& light = light_direction();

  for (int t = 0; t < tris.rows(); ++t) {
    const int v[3] = {tris(t, 0), tris(t, 1), tris(t, 2)};
    const Vec3 &p0 = screen[v[0]], &p1 = screen[v[1]], &p2 = screen[v[2]];
    const double area = (p1.x() - p0.x()) * (p2.y() - p0.y()) - (p1.y() - p0.y()) * (p2.x() - p0.x());
    if (std::abs(area) < 1e-12) continue;  // edge-on or degenerate: covers no pixel centre
    const int ix0 = std::max(xa, int(std::floor(std::min({p0.x(), p1.x(), p2.x()}))));
    const int ix1 = std::min(xb - 1, int(std::ceil(std::max({p0.x(), p1.x(), p2.x()}))));
    const int iy0 = std::max(ya, int(std::floor(std::min({p0.y(), p1.y(), p2.y()}))));
    const int iy1 = std::min(yb - 1, int(std::ceil(std::max({p0.y(), p1.y(), p2.y()}))));
    for (int y = iy0; y <= iy1; ++y)
      for (int x = ix0; x <= ix1; ++x) {
        const double sx = x + 0.5, sy = y + 0.5;
        // Barycentrics from edge functions; dividing by the signed area makes
        // them orientation independent.
        const double w0 = ((p1.x() - sx) * (p2.y() - sy) - (p1.y() - sy) * (p2.x() - sx)) / area;
        const double w1 = ((p2.x() - sx) * (p0.y() - sy) - (p2.y() - sy) * (p0.x() - sx)) / area;
        const double w2 = 1 - w0 - w1;
        constexpr double eps = -1e-9;  // shared edges: draw both sides rather than leave cracks
        if (w0 < eps || w1 < eps || w2 < eps) continue;
        const double z = w0 * p0.z() + w1 * p1.z() + w2 * p2.z();
        double& zb = zbuf[size_t(y - ya) * zw + (x - xa)];
        if (z >= zb) continue;
        zb = z;
        Vec3 n = w0 * normals[v[0]] + w1 * normals[v[1]] + w2 * normals[v[2]];
        n = n.squaredNorm() > 1e-20 ? Vec3(n.normalized()) : Vec3::UnitZ();
        if (n.z() < 0) n = -n;  // two-sided: the camera looks along -z
        const double shade = kAmbient + (1 - kAmbient) * std::max(0.0, n.dot(light));
        const Vec3 c = shade * (w0 * rgb(v[0]) + w1 * rgb(v[1]) + w2 * rgb(v[2]));
        auto ch = [](double u) { return uint8_t(std::lround(std::clamp(u, 0.0, 255.0))); };
        img.set(x, y, Rgb{ch(c.x()), ch(c.y()), ch(c.z())});
      }
  }
}

}  // namespace facesr
