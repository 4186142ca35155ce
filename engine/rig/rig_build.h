#pragma once
#include <string>

#include "rig/head_source.h"
#include "rig/procedural_head.h"
#include "rig/rig.h"

namespace facesr {

struct RigBuildOptions {
  std::string source = "procedural";  // "procedural" or an ICT FaceKit folder
  std::string muscles_path;           // muscle spec JSON; empty = built-in
  double flesh_grid_h = 0.2;          // cm, signed-distance grid for the flesh
  double bone_edge = 0.5;             // cm, bone surface edge length
  double hr_max_volume = 0.008;       // cm³, TetGen -a (0 = none)
  double hr_radius_edge = 1.6;        // TetGen -q radius-edge bound
  double lr_cell = 0.8;               // cm, lattice cell size
  double min_hr_over_lr = 20;         // coarsen the lattice until hr_tets/lr_tets reaches this
  double max_predeform_deg = 20;      // give up on lip separation beyond this
  ProceduralOptions procedural;
  bool verbose = true;
};

// Builds the anatomical rig from a head: bones and jaw, HR conforming tets,
// LR lattice, embeddings, muscles, attachments, tracks (paper §4).
Rig build_rig(const RigBuildOptions& opt);

// Rigid motion of each jaw shape from its lower teeth, and the jawOpen hinge.
Jaw fit_jaw(const HeadSource& src);

// Upper and lower lip vertex sets on the face surface (for checks and tests).
void lip_vertices(const Rig& rig, std::vector<int>& upper, std::vector<int>& lower);

}  // namespace facesr
