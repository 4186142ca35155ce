#pragma once
#include <vector>

#include "dataset/dataset_io.h"

// What the super-resolution step has to make up for: how far the face
// surface carried by the LR lattice is from the HR simulation's surface.
namespace facesr {

// Per-vertex Euclidean distance |hr_disp - embedded_disp| (cm) over the S
// face-surface vertices of one frame: its mean and maximum (0 and 0 for no
// vertices). Displacements, not positions, are compared, so any rest-pose
// difference between the embedded and the HR surface does not count. Throws
// Error when the two arrays differ in size or are not whole vertices.
void embedded_error(const DatasetFrame& f, double& mean_cm, double& max_cm);

// The per-vertex distances themselves (S floats, cm), e.g. for a heat map.
std::vector<float> embedded_error_per_vertex(const DatasetFrame& f);

}  // namespace facesr
