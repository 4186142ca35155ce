#pragma once
#include <string>
#include <vector>

#include "render/preview_raster.h"
#include "rig/rig.h"

// Pictures of where a face surface is wrong: each panel is a front view of
// one surface, skin coloured by a per-vertex error in cm on one heat scale
// shared by all panels (e.g. the LR-embedded surface against the HR one, or
// a network's prediction against the HR target).
namespace facesr {

// A near-square grid of panels of `tile_width` pixels (height from the
// face's aspect ratio), each a front view of positions[i] (S x 3 floats, cm,
// over rig.surface_tris) coloured by error_cm[i] (S floats) on a heat scale
// from 0 to scale_max_cm (larger errors saturate), labelled labels[i], under
// a title and above a legend in cm. All panels share one camera framed on the
// bounding box of every panel. Throws Error (before writing anything) on
// mismatched counts or sizes, non-finite values, a scale that is not > 0 or
// sizes out of range; the PNG is written atomically.
void render_error_png(const Rig& rig, const std::vector<std::vector<float>>& positions,
                      const std::vector<std::vector<float>>& error_cm, const std::vector<std::string>& labels,
                      double scale_max_cm, const std::string& png_path, int tile_width = 360);

// The same picture, in memory.
Image render_error_image(const Rig& rig, const std::vector<std::vector<float>>& positions,
                         const std::vector<std::vector<float>>& error_cm, const std::vector<std::string>& labels,
                         double scale_max_cm, int tile_width = 360);

}  // namespace facesr
