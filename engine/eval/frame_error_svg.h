#pragma once
#include <string>
#include <vector>

#include "eval/frame_id.h"

namespace facesr {

// A line plot like the paper's fig. 5, as standalone SVG text: x = test frame
// index running across the test sequences in order (dashed separators and
// the sequence names mark where each starts), y = mean per-vertex error (cm)
// from 0, one coloured polyline per method (the method named "ours" in red,
// as in the paper), ticks and labels on both axes, a legend and `title`.
// frame_means[m][f] belongs to methods[m] and frames[f]. Throws Error on
// mismatched counts or non-finite values.
std::string frame_error_svg(const std::vector<FrameId>& frames, const std::vector<std::string>& methods,
                            const std::vector<std::vector<double>>& frame_means, const std::string& title);

// The same, written atomically to `path`.
void write_frame_error_svg(const std::string& path, const std::vector<FrameId>& frames,
                           const std::vector<std::string>& methods, const std::vector<std::vector<double>>& frame_means,
                           const std::string& title);

// A step of 1, 2 or 5 times a power of ten that cuts `range` into about
// `target` intervals (the tick spacing of the plot axes).
double nice_tick_step(double range, int target);

}  // namespace facesr
