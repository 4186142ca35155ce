#pragma once
// Linear interpolation of two trained models' weights, (1 − t)·a + t·b
// ("model soup", Wortsman et al. 2022): two fine-tunes of one model that each
// do better on a different part of the data often do better on both when
// their weights are averaged. Only models of the same architecture, rig and
// rest-pose geometry can be blended; anything else is an Error naming what
// differs.
#include <string>

#include "sr/sr_model.h"

namespace facesr {

// t in [0, 1]. The result keeps a's header and geometry and records both
// sources and t under training["blend"]. `context` starts every Error.
SrModel blend_sr_models(const SrModel& a, const SrModel& b, double t, const std::string& context);

}  // namespace facesr
