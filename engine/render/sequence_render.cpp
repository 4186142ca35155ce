#include "render/sequence_render.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "render/heat_legend.h"
#include "render/mesh_raster.h"
#include "render/panel_style.h"
#include "render/rig_preview.h"

namespace facesr {
namespace {

using namespace panel_style;

std::string format(const char* fmt, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

void validate(const Rig& rig, const Sequence& seq, const std::vector<int>& frames, const RenderOptions& opt) {
  const std::string who = "render: ";
  const int S = rig.num_surface_vertices();
  require(S > 0 && rig.surface_tris.rows() > 0, who + "rig '" + rig.name + "' has an empty face surface");
  require(seq.header.num_surface == uint64_t(S), who + "the sequence has " + std::to_string(seq.header.num_surface) +
                                                     " surface vertices but rig '" + rig.name + "' has " +
                                                     std::to_string(S) + " (was it simulated with another rig?)");
  const int F = seq.frames();
  require(F > 0, who + "the sequence has no frames");
  require(seq.surface.size() == size_t(F) * S * 3, who + "the sequence holds " + std::to_string(seq.surface.size()) +
                                                       " surface floats, expected " +
                                                       std::to_string(size_t(F) * S * 3));
  require(!frames.empty(), who + "no frames chosen");
  require(frames.size() <= size_t(kMaxPanels), who + std::to_string(frames.size()) + " frames chosen, at most " +
                                                   std::to_string(kMaxPanels) + " fit in one image");
  for (int f : frames)
    require(f >= 0 && f < F, who + "frame " + std::to_string(f) + " is out of range (the sequence has " +
                                 std::to_string(F) + " frames, 0.." + std::to_string(F - 1) + ")");
  require(opt.tile_width >= 64 && opt.tile_width <= 4096,
          who + "tile width " + std::to_string(opt.tile_width) + " is outside [64, 4096]");
  require(opt.tile_height == 0 || (opt.tile_height >= 64 && opt.tile_height <= 4096),
          who + "tile height " + std::to_string(opt.tile_height) + " is outside [64, 4096] (or 0 for automatic)");
  require(opt.columns >= 0, who + "columns must not be negative");
}

}  // namespace

Rgb heat_colour(double s) {
  static const double stops[4][3] = {{40, 60, 200}, {40, 200, 220}, {240, 220, 40}, {220, 40, 30}};
  s = std::clamp(std::isfinite(s) ? s : 0.0, 0.0, 1.0) * 3;
  const int i = std::min(2, int(s));
  const double u = s - i;
  auto ch = [&](int k) { return uint8_t(std::lround(stops[i][k] + u * (stops[i + 1][k] - stops[i][k]))); };
  return {ch(0), ch(1), ch(2)};
}

std::vector<float> surface_displacement_cm(const Sequence& seq, int frame) {
  const size_t S = seq.header.num_surface;
  const float* x0 = seq.frame_surface(0);
  const float* x = seq.frame_surface(frame);
  std::vector<float> d(S);
  for (size_t v = 0; v < S; ++v) {
    const double dx = x[3 * v] - x0[3 * v], dy = x[3 * v + 1] - x0[3 * v + 1], dz = x[3 * v + 2] - x0[3 * v + 2];
    d[v] = float(std::sqrt(dx * dx + dy * dy + dz * dz));
  }
  return d;
}

double max_surface_displacement_cm(const Sequence& seq) {
  double m = 0;
  for (int f = 1; f < seq.frames(); ++f)
    for (float d : surface_displacement_cm(seq, f)) m = std::max(m, double(d));
  return m;
}

std::vector<int> evenly_spaced_frames(int num_frames, int count) {
  std::vector<int> out;
  if (num_frames <= 0 || count <= 0) return out;
  if (count == 1) return {0};
  for (int i = 0; i < count; ++i) {
    const int f = int(std::lround(double(i) * (num_frames - 1) / (count - 1)));
    if (out.empty() || f != out.back()) out.push_back(f);
  }
  return out;
}

Image render_sequence_image(const Rig& rig, const Sequence& seq, const std::vector<int>& frames,
                            const RenderOptions& opt, RenderSummary* summary) {
  validate(rig, seq, frames, opt);
  const int S = rig.num_surface_vertices(), n = int(frames.size());

  // One box over every frame, not just the chosen ones, so the framing does
  // not depend on which frames are shown.
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  extend_box(seq.surface.data(), size_t(seq.frames()) * S, lo, hi);

  const int tw = opt.tile_width;
  const int fs = std::max(1, int(std::lround(tw / 240.0)));  // font pixel size
  const int label_h = text_height(fs) + 4 * fs;
  const double aspect = std::max(hi.y() - lo.y(), 1e-9) / std::max(hi.x() - lo.x(), 1e-9);
  const int th = opt.tile_height > 0 ? opt.tile_height : std::clamp(label_h + int(std::lround(tw * aspect)), 64, 4096);
  const int cols =
      opt.columns > 0 ? std::min(opt.columns, n) : std::clamp(int(std::lround(std::sqrt(double(n) * th / tw))), 1, n);
  const int rows = (n + cols - 1) / cols;
  const int title_h = text_height(fs) + 6 * fs;
  const int legend_h = opt.heat ? heat_legend_height(fs) : 0;
  const long W = long(cols) * tw, H = title_h + long(rows) * th + legend_h;
  require(W <= kMaxSide && H <= kMaxSide, "render: the image would be " + std::to_string(W) + " x " +
                                              std::to_string(H) + " pixels, more than " + std::to_string(kMaxSide) +
                                              " on a side (choose fewer frames or a smaller tile width)");

  const double max_cm = max_surface_displacement_cm(seq);
  Image img(int(W), int(H), kBackground);
  std::string title = "rig " + (rig.name.empty() ? std::string("(unnamed)") : rig.name) + "  " + seq.header.resolution +
                      " res  " + std::to_string(seq.frames()) + " frames  " + format("%g fps", seq.header.fps) +
                      "  units: cm";
  int title_fs = fs;
  while (title_fs > 1 && text_width(title, title_fs) > W - 6 * fs) --title_fs;
  draw_text(img, 3 * fs, 3 * fs, title, kInk, title_fs);

  Progress progress("render", n, opt.verbose);
  std::vector<Rgb> colours;
  for (int i = 0; i < n; ++i) {
    const int f = frames[i];
    const int x = (i % cols) * tw, y = title_h + (i / cols) * th;
    const FrontView view = frame_front_view(lo, hi, x, y + label_h, tw, th - label_h);
    if (opt.heat) {
      const std::vector<float> d = surface_displacement_cm(seq, f);
      colours.resize(S);
      for (int v = 0; v < S; ++v) colours[v] = heat_colour(max_cm > 0 ? d[v] / max_cm : 0.0);
    }
    rasterize_mesh(img, view, seq.frame_surface(f), S, rig.surface_tris, colours, preview_skin_colour());
    draw_label(img, x + 2 * fs, y + 2 * fs, "frame " + std::to_string(f) + "  t=" + format("%.2f", seq.time[f]) + "s",
               kInk, fs);
    img.fill_rect(x, y, 1, th, kGridLine);
    img.fill_rect(x, y, tw, 1, kGridLine);
    progress.update(i + 1);
  }
  progress.finish();
  if (opt.heat) draw_heat_legend(img, title_h + rows * th, fs, max_cm, "displacement from frame 0 (cm)", kInk);
  if (summary) *summary = RenderSummary{int(W), int(H), max_cm};
  return img;
}

RenderSummary render_sequence_png(const Rig& rig, const Sequence& seq, const std::vector<int>& frames,
                                  const std::string& png_path, const RenderOptions& opt) {
  RenderSummary summary;
  const Image img = render_sequence_image(rig, seq, frames, opt, &summary);
  const std::vector<uint8_t> png = img.encode_png();
  write_file_atomically(png_path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(png.data()), std::streamsize(png.size()));
  });
  return summary;
}

}  // namespace facesr
