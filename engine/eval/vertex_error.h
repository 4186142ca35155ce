#pragma once
#include <string>
#include <vector>

// Per-vertex reconstruction error of a super-resolved surface (paper §5.2):
// the Euclidean distance between the predicted and the reference position of
// each HR surface vertex. Both surfaces are given as displacements from the
// same rest surface, so the distance is that of the displacements.
namespace facesr {

// |predicted - reference| per vertex (cm); both arrays M x 3 floats (cm).
// Throws Error naming `who` when the sizes differ, are not whole vertices or
// a value is not finite.
std::vector<double> vertex_error(const std::vector<float>& predicted_disp, const std::vector<float>& reference_disp,
                                 const std::string& who = "vertex error");

// Mean of vertex_error() over the vertices: the paper's frame-wise error (fig. 5).
double frame_mean_error(const std::vector<float>& predicted_disp, const std::vector<float>& reference_disp,
                        const std::string& who = "frame mean error");

}  // namespace facesr
