#pragma once
#include <string>
#include <vector>

#include "render/preview_raster.h"
#include "rig/rig.h"

namespace facesr {

struct PreviewOptions {
  int width = 1200;          // pixels, in [64, 8192]
  int height = 900;          // pixels, in [64, 8192]
  bool show_lattice = true;  // outline of the LR lattice boundary
  bool show_legend = true;   // muscle colour key
};

// Writes a PNG with two orthographic views of the face surface (front, and
// rotated 60° about +y), each auto-framed on the surface. Skin is coloured by
// the muscle found just beneath it in the HR mesh; the LR lattice boundary is
// overlaid. Throws Error on an empty surface or an out-of-range size.
void render_rig_preview(const Rig& rig, const std::string& png_path,
                        const PreviewOptions& opt = PreviewOptions{});

// Unshaded colours the preview uses; mirror pairs (names ending in _L/_R,
// .L/.R, _left/_right) share a hue, the right side darker.
Rgb preview_skin_colour();
Rgb preview_muscle_colour(const std::vector<std::string>& muscle_names, int muscle_id);

}  // namespace facesr
