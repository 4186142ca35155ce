#include "render/heat_legend.h"

#include <algorithm>
#include <cstdio>

#include "render/sequence_render.h"

namespace facesr {

void draw_label(Image& img, int x, int y, const std::string& text, Rgb c, int fs) {
  std::string rest = text;
  for (size_t i = 0; i < rest.size(); ++i)
    if (rest[i] == '=') {
      const int gx = x + int(i) * 6 * fs;
      img.fill_rect(gx, y + 2 * fs, 5 * fs, fs, c);
      img.fill_rect(gx, y + 4 * fs, 5 * fs, fs, c);
      rest[i] = ' ';
    }
  draw_text(img, x, y, rest, c, fs);
}

void draw_heat_legend(Image& img, int y0, int fs, double max_cm, const std::string& title, Rgb ink) {
  const int margin = 4 * fs, th = text_height(fs);
  draw_text(img, margin, y0 + margin, title, ink, fs);
  const int bar_y = y0 + margin + th + 2 * fs, bar_h = th + fs;
  const int bar_w = std::max(16, std::min(img.width() - 2 * margin, 200 * fs));
  for (int i = 0; i < bar_w; ++i) img.fill_rect(margin + i, bar_y, 1, bar_h, heat_colour(double(i) / (bar_w - 1)));
  const int label_y = bar_y + bar_h + fs;
  draw_text(img, margin, label_y, "0 cm", ink, fs);
  char hi[64];
  std::snprintf(hi, sizeof hi, "%.3g cm", max_cm);
  draw_text(img, std::max(margin, margin + bar_w - text_width(hi, fs)), label_y, hi, ink, fs);
}

}  // namespace facesr
