#pragma once
#include <string>

#include "render/preview_raster.h"

// Text drawn over rendered panels, shared by the sequence and error pictures
// so that their labels and heat legends look the same.
namespace facesr {

// draw_text, plus '=' (the 5x7 font has none, and labels read "t=1.00s").
void draw_label(Image& img, int x, int y, const std::string& text, Rgb c, int fs);

// Pixels of height draw_heat_legend needs at font size fs.
inline int heat_legend_height(int fs) { return 3 * text_height(fs) + 12 * fs; }

// `title`, then a heat_colour bar from 0 to max_cm labelled "0 cm" and the
// maximum, starting at row y0.
void draw_heat_legend(Image& img, int y0, int fs, double max_cm, const std::string& title, Rgb ink);

}  // namespace facesr
