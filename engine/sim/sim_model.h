#pragma once
#include <string>
#include <vector>

#include "rig/rig.h"
#include "sim/material.h"

namespace facesr {

enum class Resolution { Low, High };
Resolution parse_resolution(const std::string& s);  // "low" | "high"
const char* resolution_name(Resolution r);

// Everything a simulator needs about one simulation mesh of a rig, flattened
// into arrays (the immutable "model"; per-run state lives in the simulators).
// Positions are in the mesh's own rest frame: for LR that is the lip-separating
// predeformed frame (rig.predeform), for HR the rig's rest pose. cm throughout.
struct SimModel {
  Resolution res = Resolution::Low;
  MaterialParams material;
  int num_nodes = 0, num_tets = 0, num_surface = 0, num_muscles = 0, num_shapes = 0;

  std::vector<double> rest;       // node × 3
  std::vector<int32_t> tets;      // tet × 4
  std::vector<double> Dminv;      // tet × 9, inverse rest edge matrix (row-major)
  std::vector<double> volume;     // tet, cm³
  std::vector<double> fibre;      // tet × 3, unit
  std::vector<double> phi;        // tet, muscle volume fraction (0 for passive flesh)
  std::vector<int32_t> muscle;    // tet, -1 for none
  std::vector<uint8_t> node_bone;  // node: 0 free, 1 cranium (fixed), 2 jaw (moves rigidly)

  // Face surface embedded in the mesh: 4 nodes and weights per vertex.
  std::vector<int32_t> surf_nodes;  // vertex × 4
  std::vector<double> surf_weights;  // vertex × 4
  std::vector<double> surf_rest;     // vertex × 3, embedded rest position
  std::vector<double> track_k;       // vertex: track spring stiffness (kPa·cm = force/cm), 0 if none

  std::vector<std::string> shape_names, muscle_names;
  std::vector<float> shape_deltas;  // shape × vertex × 3 (cm), linear blendshape model
  std::vector<float> activation;    // shape × muscle, activation per unit weight
  Jaw jaw;
  double mean_edge = 0;  // cm
  double face_size = 0;  // cm, diagonal of the surface bounding box

  // Node → incidence slots for race-free gathers: slot 4t+k is corner k of
  // tet t, slot 4·num_tets + 4i + k is corner k of the i-th vertex of a
  // surface list. Two lists: every surface vertex (needed when point springs
  // or spheres may touch any vertex), and only the tracked vertices (enough
  // otherwise, and far fewer on the LR lattice).
  struct Incidence {
    std::vector<int32_t> vertices;  // the surface list
    std::vector<int32_t> offset;    // node + 1
    std::vector<int32_t> slot;
  };
  Incidence inc_all, inc_tracked;
};

SimModel make_sim_model(const Rig& rig, Resolution res, const MaterialParams& material = {});

}  // namespace facesr
