#include "render/rig_preview.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <utility>

#include "core/atomic_file.h"
#include "core/error.h"
#include "mesh/surface_query.h"
#include "mesh/tet_locator.h"
#include "mesh/tri_mesh.h"
#include "render/panel_style.h"

namespace facesr {
namespace {

constexpr double kSideAngleDeg = 60;
constexpr double kMinMuscleFraction = 0.25;
constexpr double kLightAmbient = 0.2;
using panel_style::kBackground;
using panel_style::kInk;
const Rgb kLatticeColour{20, 40, 150};

// Strips a side suffix so that mirror pairs map to one key; side is 0 for
// unpaired names, 1 for left, 2 for right.
std::pair<std::string, int> mirror_key(const std::string& name) {
  std::string low(name);
  for (char& c : low) c = char(std::tolower(static_cast<unsigned char>(c)));
  static const std::pair<const char*, int> suffixes[] = {{"_left", 1}, {"_right", 2}, {"_l", 1},
                                                         {"_r", 2},    {".l", 1},     {".r", 2}};
  for (const auto& [suffix, side] : suffixes) {
    const size_t n = std::char_traits<char>::length(suffix);
    if (low.size() > n && low.compare(low.size() - n, n, suffix) == 0)
      return {low.substr(0, low.size() - n), side};
  }
  return {low, 0};
}

std::vector<Rgb> muscle_palette(const std::vector<std::string>& names, int count) {
  // Saturated hues well away from the skin tone, so muscle regions read at a glance.
  static const Rgb base[] = {{31, 119, 180}, {44, 160, 44},  {214, 39, 40},   {148, 103, 189},
                             {23, 190, 207}, {188, 189, 34}, {227, 119, 194}, {255, 127, 14},
                             {0, 128, 128},  {128, 0, 64},   {90, 90, 220},   {140, 86, 75}};
  constexpr int kBase = int(sizeof(base) / sizeof(base[0]));
  std::map<std::string, int> group_of;
  std::vector<Rgb> out(count);
  for (int id = 0; id < count; ++id) {
    const auto [key, side] = id < int(names.size()) ? mirror_key(names[id])
                                                    : std::make_pair("#" + std::to_string(id), 0);
    const int group = group_of.emplace(key, int(group_of.size())).first->second;
    Rgb c = base[group % kBase];
    // Past the first cycle, tint toward white so repeated hues stay distinguishable.
    const double lighten = (group / kBase) % 2 ? 0.4 : 0.0;
    const double shade = side == 2 ? 0.7 : 1.0;
    auto mix = [&](uint8_t v) { return uint8_t(std::lround(shade * (v + lighten * (255 - v)))); };
    out[id] = {mix(c.r), mix(c.g), mix(c.b)};
  }
  return out;
}

Vec3 to_vec(Rgb c) { return Vec3(c.r, c.g, c.b); }
Rgb to_rgb(const Vec3& v) {
  auto ch = [](double x) { return uint8_t(std::lround(std::clamp(x, 0.0, 255.0))); };
  return {ch(v.x()), ch(v.y()), ch(v.z())};
}

// Muscle id under each surface vertex (-1: none), found by probing the HR
// mesh along the inward normal; done per vertex so pixels only interpolate.
std::vector<int> muscle_under_vertices(const Rig& rig, const Points& normals) {
  const int nv = int(rig.surface.rows());
  std::vector<int> out(nv, -1);
  const SimMesh& hr = rig.hr;
  if (hr.mesh.T.rows() == 0 || hr.muscle.empty()) return out;
  require(hr.muscle.size() == size_t(hr.mesh.T.rows()) &&
              hr.muscle_fraction.size() == size_t(hr.mesh.T.rows()),
          "render_rig_preview: rig '" + rig.name + "' has " + std::to_string(hr.muscle.size()) +
              " muscle ids and " + std::to_string(hr.muscle_fraction.size()) + " fractions for " +
              std::to_string(hr.mesh.T.rows()) + " HR tets");
  const TetLocator locator(hr.mesh);
#pragma omp parallel for schedule(dynamic, 64)
  for (int v = 0; v < nv; ++v) {
    const Vec3 p = rig.surface.row(v).transpose();
    const Vec3 n = normals.row(v).transpose();
    for (double depth = 0.1; depth <= 1.5 + 1e-9; depth += 0.15) {
      const TetLocator::Result r = locator.locate(p - depth * n);
      // locate() falls back to a nearby tet for outside points; only accept containment.
      if (r.tet < 0 || r.bary.minCoeff() < -1e-6) continue;
      if (hr.muscle[r.tet] >= 0 && hr.muscle_fraction[r.tet] > kMinMuscleFraction) {
        out[v] = hr.muscle[r.tet];
        break;
      }
    }
  }
  return out;
}

// Edges of the LR lattice's outer hull: cube edges (axis-aligned) lying on
// boundary faces, which skips the cube-splitting diagonals.
std::vector<std::pair<int, int>> lattice_outline(const TetMesh& m) {
  std::vector<std::array<int, 3>> faces;
  faces.reserve(size_t(m.T.rows()) * 4);
  for (int t = 0; t < m.T.rows(); ++t)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f;
      for (int k = 0, j = 0; k < 4; ++k)
        if (k != skip) f[j++] = m.T(t, k);
      std::sort(f.begin(), f.end());
      faces.push_back(f);
    }
  std::sort(faces.begin(), faces.end());
  std::vector<std::pair<int, int>> edges;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j] == faces[i]) ++j;
    if (j - i == 1) {
      const auto& f = faces[i];
      for (int k = 0; k < 3; ++k) {
        const int a = f[k], b = f[(k + 1) % 3];
        const Vec3 d = (m.X.row(b) - m.X.row(a)).transpose().cwiseAbs();
        const int axes = (d.array() > 1e-3 * d.maxCoeff()).count();
        if (axes == 1) edges.emplace_back(std::min(a, b), std::max(a, b));
      }
    }
    i = j;
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  return edges;
}

// Orthographic camera mapped onto a pixel rectangle of the image.
struct View {
  Vec3 right, up, fwd;  // fwd points from the camera into the scene
  Vec3 centre;
  double px_per_cm = 1;
  int x0 = 0, y0 = 0, w = 1, h = 1;

  View(double yaw_deg, const Points& V, int x, int y, int width, int height)
      : x0(x), y0(y), w(width), h(height) {
    const double a = yaw_deg * M_PI / 180;
    right = Vec3(std::cos(a), 0, -std::sin(a));
    up = Vec3::UnitY();
    fwd = -Vec3(std::sin(a), 0, std::cos(a));
    Vec3 lo, hi;
    bounding_box(V, lo, hi);
    centre = 0.5 * (lo + hi);
    double xmin = 1e300, xmax = -1e300, ymin = 1e300, ymax = -1e300;
    for (int i = 0; i < V.rows(); ++i) {
      const Vec3 d = V.row(i).transpose() - centre;
      xmin = std::min(xmin, d.dot(right));
      xmax = std::max(xmax, d.dot(right));
      ymin = std::min(ymin, d.dot(up));
      ymax = std::max(ymax, d.dot(up));
    }
    centre += 0.5 * (xmin + xmax) * right + 0.5 * (ymin + ymax) * up;
    const double ex = std::max(xmax - xmin, 1e-9), ey = std::max(ymax - ymin, 1e-9);
    px_per_cm = 0.9 * std::min(w / ex, h / ey);
  }
  // Image position (x, y) and depth along fwd of a world point.
  Vec3 project(const Vec3& p) const {
    const Vec3 d = p - centre;
    return Vec3(x0 + 0.5 * w + d.dot(right) * px_per_cm, y0 + 0.5 * h - d.dot(up) * px_per_cm,
                d.dot(fwd));
  }
  // World point on the plane through `centre` under image position (x, y).
  Vec3 unproject(double x, double y) const {
    return centre + right * ((x - x0 - 0.5 * w) / px_per_cm) -
           up * ((y - y0 - 0.5 * h) / px_per_cm);
  }
  bool contains(int x, int y) const { return x >= x0 && y >= y0 && x < x0 + w && y < y0 + h; }
};

// Ray-casts the surface into the view's rectangle; returns per-pixel depth
// along fwd (infinity where the ray missed) for occlusion-aware overlays.
std::vector<float> render_surface(Image& img, const View& view, const SurfaceQuery& query,
                                  const Points& normals, const std::vector<Vec3>& vertex_colour,
                                  double radius) {
  std::vector<float> depth(size_t(view.w) * view.h, std::numeric_limits<float>::infinity());
  const Vec3 light = (-view.fwd + 0.5 * view.up - 0.3 * view.right).normalized();
  const Tris& F = query.triangles();
  const Points& V = query.vertices();
#pragma omp parallel for schedule(dynamic, 4)
  for (int j = 0; j < view.h; ++j) {
    for (int i = 0; i < view.w; ++i) {
      const int x = view.x0 + i, y = view.y0 + j;
      const Vec3 origin = view.unproject(x + 0.5, y + 0.5) - radius * view.fwd;
      const SurfaceQuery::RayHit hit =
          query.first_hit(origin, view.fwd, 0, std::numeric_limits<double>::infinity());
      if (hit.tri < 0) continue;
      Vec3 n = Vec3::Zero(), colour = Vec3::Zero();
      for (int k = 0; k < 3; ++k) {
        const int v = F(hit.tri, k);
        n += hit.bary[k] * normals.row(v).transpose();
        colour += hit.bary[k] * vertex_colour[v];
      }
      if (n.squaredNorm() < 1e-20) {
        const Vec3 a = V.row(F(hit.tri, 0)), b = V.row(F(hit.tri, 1)), c = V.row(F(hit.tri, 2));
        n = (b - a).cross(c - a);
      }
      n.normalize();
      if (n.dot(view.fwd) > 0) n = -n;  // back faces (open boundaries, lips) lit as front
      const double shade = kLightAmbient + (1 - kLightAmbient) * std::max(0.0, n.dot(light));
      img.set(x, y, to_rgb(shade * colour));
      depth[size_t(j) * view.w + i] = float(hit.t - radius);
    }
  }
  return depth;
}

void draw_lattice(Image& img, const View& view, const std::vector<float>& depth, const TetMesh& lr,
                  const std::vector<std::pair<int, int>>& edges) {
  const double eps = 0.02;  // cm: keeps lines lying on the surface counted as visible
  for (const auto& [a, b] : edges) {
    const Vec3 pa = view.project(lr.X.row(a).transpose());
    const Vec3 pb = view.project(lr.X.row(b).transpose());
    rasterize_line(pa.x(), pa.y(), pb.x(), pb.y(), [&](int x, int y, double s) {
      if (!view.contains(x, y)) return;
      const double z = pa.z() + s * (pb.z() - pa.z());
      const bool hidden = z > depth[size_t(y - view.y0) * view.w + (x - view.x0)] + eps;
      img.blend(x, y, kLatticeColour, hidden ? 0.25 : 0.6);
    });
  }
}

// A bar of a round length (1-2-5 series) about a quarter of the panel's smaller side.
void draw_scale_bar(Image& img, const View& view, const std::string& units, int fs) {
  double len = 0.1;
  for (double decade = 0.1; decade < 1e4; decade *= 10)
    for (double m : {1.0, 2.0, 5.0})
      if (m * decade * view.px_per_cm <= 0.25 * std::min(view.w, view.h)) len = m * decade;
  const int px = int(std::lround(len * view.px_per_cm));
  const int x = view.x0 + 4 * fs, y = view.y0 + view.h - 4 * fs;
  img.fill_rect(x, y, px, fs, kInk);
  img.fill_rect(x, y - 2 * fs, fs, 3 * fs, kInk);
  img.fill_rect(x + px - fs, y - 2 * fs, fs, 3 * fs, kInk);
  char label[32];
  std::snprintf(label, sizeof label, "%g %s", len, units.c_str());
  draw_text(img, x, y - 3 * fs - text_height(fs), label, kInk, fs);
}

struct LegendLayout {
  int rows = 0, cols = 0, col_w = 0, row_h = 0, height = 0;
};

LegendLayout layout_legend(const std::vector<std::string>& names, int width, int max_height,
                           int fs) {
  LegendLayout L;
  if (names.empty()) return L;
  size_t longest = 0;
  for (const auto& n : names) longest = std::max(longest, n.size());
  L.row_h = text_height(fs) + 4 * fs;
  L.col_w = text_height(fs) + 4 * fs + text_width(std::string(longest, 'M'), fs) + 8 * fs;
  const int margin = 4 * fs;
  L.cols = std::max(1, (width - 2 * margin) / L.col_w);
  const int max_rows = (max_height - 2 * margin) / L.row_h;
  L.rows = std::min<int>((int(names.size()) + L.cols - 1) / L.cols, max_rows);
  L.height = L.rows > 0 ? L.rows * L.row_h + 2 * margin : 0;
  return L;
}

void draw_legend(Image& img, const std::vector<std::string>& names, const std::vector<Rgb>& colours,
                 const LegendLayout& L, int y0, int fs) {
  const int margin = 4 * fs, sq = text_height(fs);
  // Column-major so alphabetised or paired names stay adjacent when read down.
  for (int i = 0; i < int(names.size()) && i < L.rows * L.cols; ++i) {
    const int x = margin + (i / L.rows) * L.col_w, y = y0 + margin + (i % L.rows) * L.row_h;
    img.fill_rect(x - 1, y - 1, sq + 2, sq + 2, kInk);
    img.fill_rect(x, y, sq, sq, colours[i]);
    draw_text(img, x + sq + 4 * fs, y, names[i], kInk, fs);
  }
}

}  // namespace

Rgb preview_skin_colour() { return {226, 188, 165}; }

Rgb preview_muscle_colour(const std::vector<std::string>& muscle_names, int muscle_id) {
  require(muscle_id >= 0, "preview_muscle_colour: negative muscle id");
  return muscle_palette(muscle_names, muscle_id + 1)[muscle_id];
}

void render_rig_preview(const Rig& rig, const std::string& png_path, const PreviewOptions& opt) {
  const std::string who = "render_rig_preview: ";
  require(rig.surface.rows() > 0 && rig.surface_tris.rows() > 0,
          who + "rig '" + rig.name + "' has an empty face surface");
  for (const auto& [what, v] :
       {std::make_pair("width", opt.width), std::make_pair("height", opt.height)})
    require(v >= 64 && v <= 8192, who + what + " " + std::to_string(v) + " is outside [64, 8192]");

  const int W = opt.width, H = opt.height;
  const int fs = std::max(1, int(std::lround(std::min(W, H) / 450.0)));  // font pixel size
  Image img(W, H, kBackground);

  const Points normals = vertex_normals(rig.surface, rig.surface_tris);
  const std::vector<int> vertex_muscle = muscle_under_vertices(rig, normals);
  int num_ids = int(rig.muscles.size());
  for (int m : vertex_muscle) num_ids = std::max(num_ids, m + 1);
  std::vector<std::string> names;
  for (const Muscle& m : rig.muscles) names.push_back(m.name);
  const std::vector<Rgb> palette = muscle_palette(names, num_ids);
  std::vector<Vec3> vertex_colour(vertex_muscle.size());
  for (size_t v = 0; v < vertex_muscle.size(); ++v)
    vertex_colour[v] =
        to_vec(vertex_muscle[v] >= 0 ? palette[vertex_muscle[v]] : preview_skin_colour());

  // Layout: title strip, two panels side by side, legend strip.
  const int title_h = text_height(fs) + 6 * fs;
  const LegendLayout legend =
      opt.show_legend ? layout_legend(names, W, (H - title_h) / 3, fs) : LegendLayout{};
  const int panel_y = title_h, panel_h = std::max(1, H - title_h - legend.height);
  const View views[2] = {View(0, rig.surface, 0, panel_y, W / 2, panel_h),
                         View(kSideAngleDeg, rig.surface, W / 2, panel_y, W - W / 2, panel_h)};

  Vec3 lo, hi;
  bounding_box(rig.surface, lo, hi);
  const double radius = (hi - lo).norm() + 1;  // rays start outside the surface
  const SurfaceQuery query(rig.surface, rig.surface_tris);
  const std::vector<std::pair<int, int>> outline = opt.show_lattice && rig.lr.mesh.T.rows() > 0
                                                       ? lattice_outline(rig.lr.mesh)
                                                       : std::vector<std::pair<int, int>>{};
  for (const View& view : views) {
    const std::vector<float> depth =
        render_surface(img, view, query, normals, vertex_colour, radius);
    draw_lattice(img, view, depth, rig.lr.mesh, outline);
  }

  const std::string units = rig.units.empty() ? "cm" : rig.units;
  draw_text(img, 3 * fs, 3 * fs,
            "rig " + (rig.name.empty() ? std::string("(unnamed)") : rig.name) +
                "  units: " + units + "  muscles: " + std::to_string(rig.muscles.size()),
            kInk, fs);
  draw_text(img, views[0].x0 + 4 * fs, panel_y + 2 * fs, "front", kInk, fs);
  draw_text(img, views[1].x0 + 4 * fs, panel_y + 2 * fs,
            "side (yaw " + std::to_string(int(kSideAngleDeg)) + ")", kInk, fs);
  img.fill_rect(W / 2, panel_y, std::max(1, fs / 2), panel_h, Rgb{100, 100, 100});
  draw_scale_bar(img, views[0], units, fs);
  if (legend.rows > 0) {
    std::vector<Rgb> key(palette.begin(), palette.begin() + names.size());
    draw_legend(img, names, key, legend, panel_y + panel_h, fs);
  }

  const std::vector<uint8_t> png = img.encode_png();
  write_file_atomically(png_path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
}

}  // namespace facesr
