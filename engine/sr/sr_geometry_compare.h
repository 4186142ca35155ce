#pragma once
// How far a model's stored rest-pose geometry is from the geometry a rig
// gives now: used to carry a trained model over to a rebuilt rig whose
// checksum changed while its content did not (`facesr model rebind`).
#include <string>

#include "sr/sr_geometry.h"

namespace facesr {

struct SrGeometryDifference {
  // Empty when every count and every integer array (graphs, assignment,
  // neighbour lists, triangles, embedding tets) is identical; else names the
  // first one that differs.
  std::string topology_mismatch;
  double max_position_cm = 0;  // rest poses (lr_rest, hr_rest, hr_rest_lr_frame)
  double max_distance_cm = 0;  // neighbour distances (up_dist, euclid_dist)
  double max_weight = 0;       // embedding weights (dimensionless)
};

// Compares the arrays `stored` holds (a model file may leave some out, a VAE
// all neighbourhoods) with the same arrays of `current`; an array that
// `stored` has and `current` lacks is a topology mismatch. pe_rows is not
// compared: it is the model's choice of encoding, not a property of the rig.
SrGeometryDifference compare_sr_geometry(const SrGeometry& stored, const SrGeometry& current);

}  // namespace facesr
