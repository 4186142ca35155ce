#pragma once
#include <functional>
#include <string>
#include <vector>

#include "rig/head_source.h"
#include "rig/rig.h"

namespace facesr {

class SurfaceQuery;

struct MuscleSet {
  std::vector<Muscle> muscles;
  // activation[b * muscles.size() + m] for the given blendshape names.
  std::vector<float> activation;
};

// Reads a muscle specification (JSON text, see engine/rig/data/muscles.json)
// and places the muscles on a head: control points at landmarks + scaled
// offsets, projected to the skin and pushed inward by their depth.
MuscleSet build_muscles(const std::string& spec_json, const std::string& spec_name, const HeadSource& src,
                        const SurfaceQuery& skin);

// The built-in default specification.
const std::string& default_muscle_spec();

// Distance from p to the muscle's centre curve, and the unit fibre direction
// (curve tangent) at the closest point.
double muscle_distance(const Muscle& m, const Vec3& p, Vec3* fibre);

// Rasterises muscles into a tet mesh: per tet the dominant muscle, its volume
// fraction and its mean fibre direction, from sample points in each tet.
// `to_rest` maps mesh-space points to the rest frame where muscles live;
// `in_flesh` says whether a rest-frame point is flesh (muscle only counts there).
void rasterize_muscles(const std::vector<Muscle>& muscles, int samples_per_tet,
                       const std::function<Vec3(const Vec3&)>& to_rest,
                       const std::function<bool(const Vec3&)>& in_flesh, SimMesh& mesh);

}  // namespace facesr
