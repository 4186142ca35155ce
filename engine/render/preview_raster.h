#pragma once
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

// Minimal RGB raster for diagnostic images (rig previews): pixels, alpha
// blending, line stepping, a 5x7 bitmap font and PNG encoding.
namespace facesr {

struct Rgb {
  uint8_t r = 0, g = 0, b = 0;
};

class Image {
 public:
  Image(int width, int height, Rgb fill);
  int width() const { return w_; }
  int height() const { return h_; }
  Rgb get(int x, int y) const;
  void set(int x, int y, Rgb c);                  // ignored outside the image
  void blend(int x, int y, Rgb c, double alpha);  // ignored outside the image
  void fill_rect(int x, int y, int w, int h, Rgb c);
  std::vector<uint8_t> encode_png() const;

 private:
  int w_, h_;
  std::vector<uint8_t> px_;  // row-major RGB
};

// Calls plot(x, y, s) for each pixel of the segment (DDA), s in [0, 1] the
// position along it, so callers can interpolate depth or colour.
template <class Plot>
void rasterize_line(double x0, double y0, double x1, double y1, Plot&& plot) {
  const double dx = x1 - x0, dy = y1 - y0;
  const int n = std::max(1, int(std::ceil(std::max(std::abs(dx), std::abs(dy)))));
  for (int i = 0; i <= n; ++i) {
    const double s = double(i) / n;
    plot(int(std::floor(x0 + s * dx)), int(std::floor(y0 + s * dy)), s);
  }
}

// 5x7 glyphs for A-Z (case-insensitive), 0-9 and " _-.:/()"; other characters
// draw as blanks. Each glyph advances 6*scale pixels.
void draw_text(Image& img, int x, int y, const std::string& text, Rgb c, int scale);
inline int text_width(const std::string& text, int scale) { return int(text.size()) * 6 * scale; }
inline int text_height(int scale) { return 7 * scale; }

}  // namespace facesr
