#pragma once
#include "render/preview_raster.h"

// Limits and colours shared by the pictures (sequence frames, error heat
// maps, the rig preview), so that they look alike.
namespace facesr::panel_style {

constexpr int kMaxSide = 16384;  // pixels: keeps a mistyped frame list from allocating gigabytes
constexpr int kMaxPanels = 1024;
inline const Rgb kBackground{120, 120, 120};
inline const Rgb kInk{20, 20, 24};
inline const Rgb kGridLine{90, 90, 90};

}  // namespace facesr::panel_style
