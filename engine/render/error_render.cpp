#include "render/error_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/heat_legend.h"
#include "render/mesh_raster.h"
#include "render/panel_style.h"
#include "render/sequence_render.h"

namespace facesr {
namespace {

using namespace panel_style;

long first_non_finite(const std::vector<float>& v) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return long(i);
  return -1;
}

void validate(const Rig& rig, const std::vector<std::vector<float>>& positions,
              const std::vector<std::vector<float>>& error_cm, const std::vector<std::string>& labels,
              double scale_max_cm, int tile_width) {
  const std::string who = "error render: ";
  const size_t S = size_t(rig.num_surface_vertices());
  require(S > 0 && rig.surface_tris.rows() > 0, who + "rig '" + rig.name + "' has an empty face surface");
  const size_t n = positions.size();
  require(n > 0, who + "no panels given");
  require(n <= size_t(kMaxPanels), who + std::to_string(n) + " panels given, at most " +
                                       std::to_string(kMaxPanels) + " fit in one image");
  require(error_cm.size() == n && labels.size() == n,
          who + std::to_string(n) + " panels of positions but " + std::to_string(error_cm.size()) +
              " of errors and " + std::to_string(labels.size()) + " labels");
  for (size_t i = 0; i < n; ++i) {
    const std::string panel = who + "panel " + std::to_string(i) + ": ";
    require(positions[i].size() == 3 * S, panel + std::to_string(positions[i].size()) +
                                              " position floats, but rig '" + rig.name + "' has " +
                                              std::to_string(S) + " surface vertices (expected " +
                                              std::to_string(3 * S) + ")");
    require(error_cm[i].size() == S, panel + std::to_string(error_cm[i].size()) + " error values, expected " +
                                         std::to_string(S) + " (one per surface vertex)");
    if (const long k = first_non_finite(positions[i]); k >= 0)
      throw Error(panel + "vertex " + std::to_string(k / 3) + " has a non-finite coordinate");
    if (const long k = first_non_finite(error_cm[i]); k >= 0)
      throw Error(panel + "the error at vertex " + std::to_string(k) + " is not finite");
  }
  require(std::isfinite(scale_max_cm) && scale_max_cm > 0,
          who + "the heat scale's maximum must be a finite number of cm > 0");
  require(tile_width >= 64 && tile_width <= 4096,
          who + "tile width " + std::to_string(tile_width) + " is outside [64, 4096]");
}

}  // namespace

Image render_error_image(const Rig& rig, const std::vector<std::vector<float>>& positions,
                         const std::vector<std::vector<float>>& error_cm, const std::vector<std::string>& labels,
                         double scale_max_cm, int tile_width) {
  validate(rig, positions, error_cm, labels, scale_max_cm, tile_width);
  const int S = rig.num_surface_vertices(), n = int(positions.size());

  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const auto& p : positions) extend_box(p.data(), size_t(S), lo, hi);

  const int tw = tile_width;
  const int fs = std::max(1, int(std::lround(tw / 240.0)));  // font pixel size
  const int label_h = text_height(fs) + 4 * fs;
  const double aspect = std::max(hi.y() - lo.y(), 1e-9) / std::max(hi.x() - lo.x(), 1e-9);
  const int th = std::clamp(label_h + int(std::lround(tw * aspect)), 64, 4096);
  const int cols = std::clamp(int(std::lround(std::sqrt(double(n) * th / tw))), 1, n);
  const int rows = (n + cols - 1) / cols;
  const int title_h = text_height(fs) + 6 * fs;
  const long W = long(cols) * tw, H = title_h + long(rows) * th + heat_legend_height(fs);
  require(W <= kMaxSide && H <= kMaxSide, "error render: the image would be " + std::to_string(W) + " x " +
                                              std::to_string(H) + " pixels, more than " + std::to_string(kMaxSide) +
                                              " on a side (show fewer panels or use a smaller tile width)");

  Image img(int(W), int(H), kBackground);
  char scale[64];
  std::snprintf(scale, sizeof scale, "%.3g", scale_max_cm);
  const std::string title = "rig " + (rig.name.empty() ? std::string("(unnamed)") : rig.name) +
                            "  per-vertex error  scale 0-" + scale + " cm";
  int title_fs = fs;
  while (title_fs > 1 && text_width(title, title_fs) > W - 6 * fs) --title_fs;
  draw_text(img, 3 * fs, 3 * fs, title, kInk, title_fs);

  std::vector<Rgb> colours(S);
  for (int i = 0; i < n; ++i) {
    const int x = (i % cols) * tw, y = title_h + (i / cols) * th;
    const FrontView view = frame_front_view(lo, hi, x, y + label_h, tw, th - label_h);
    for (int v = 0; v < S; ++v) colours[v] = heat_colour(error_cm[i][v] / scale_max_cm);
    rasterize_mesh(img, view, positions[i].data(), S, rig.surface_tris, colours, Rgb{});
    draw_label(img, x + 2 * fs, y + 2 * fs, labels[i], kInk, fs);
    img.fill_rect(x, y, 1, th, kGridLine);
    img.fill_rect(x, y, tw, 1, kGridLine);
  }
  draw_heat_legend(img, title_h + rows * th, fs, scale_max_cm, "error (cm)", kInk);
  return img;
}

void render_error_png(const Rig& rig, const std::vector<std::vector<float>>& positions,
                      const std::vector<std::vector<float>>& error_cm, const std::vector<std::string>& labels,
                      double scale_max_cm, const std::string& png_path, int tile_width) {
  const Image img = render_error_image(rig, positions, error_cm, labels, scale_max_cm, tile_width);
  const std::vector<uint8_t> png = img.encode_png();
  write_file_atomically(png_path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
}

}  // namespace facesr
