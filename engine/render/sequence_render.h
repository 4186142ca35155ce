#pragma once
#include <string>
#include <vector>

#include "perf/sequence_io.h"
#include "render/preview_raster.h"
#include "rig/rig.h"

namespace facesr {

struct RenderOptions {
  int tile_width = 360;  // pixels per frame panel, in [64, 4096]
  int tile_height = 0;   // pixels per panel, in [64, 4096]; 0: from the face's aspect ratio
  int columns = 0;       // panels per row; 0: a near-square grid
  bool heat = false;     // colour by displacement from frame 0 (cm) instead of skin
  bool verbose = false;  // progress on stderr
};

struct RenderSummary {
  int width = 0, height = 0;       // pixels of the whole image
  double max_displacement_cm = 0;  // max |x - x_frame0| over all frames and surface vertices
};

// A grid of front views of the chosen frames' face surface (rig.surface_tris
// over the sequence's per-frame surface positions), each labelled
// "frame N  t=..s". All panels share one camera framed on the bounding box of
// every frame, so motion shows as motion. With opt.heat, skin is coloured by
// displacement from frame 0 on a scale from 0 to the sequence's maximum, with
// a legend in cm. Throws Error (before writing anything) on a frame index out
// of range, a surface that does not match the rig, or sizes out of range; the
// PNG is written atomically.
RenderSummary render_sequence_png(const Rig& rig, const Sequence& seq, const std::vector<int>& frames,
                                  const std::string& png_path, const RenderOptions& opt = RenderOptions{});

// The same picture, in memory.
Image render_sequence_image(const Rig& rig, const Sequence& seq, const std::vector<int>& frames,
                            const RenderOptions& opt = RenderOptions{}, RenderSummary* summary = nullptr);

// Per-vertex |x_f - x_0| (cm) of frame f's surface.
std::vector<float> surface_displacement_cm(const Sequence& seq, int frame);

// Largest surface displacement from frame 0 over all frames (cm).
double max_surface_displacement_cm(const Sequence& seq);

// `count` frame indices spread evenly over [0, num_frames - 1], first and last
// included, without repeats (fewer when num_frames < count).
std::vector<int> evenly_spaced_frames(int num_frames, int count);

// Heat colour for s in [0, 1] (blue, cyan, yellow, red); clamped outside.
Rgb heat_colour(double s);

}  // namespace facesr
