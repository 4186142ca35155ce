#pragma once
#include <array>
#include <string>
#include <vector>

#include "mesh/tet_mesh.h"
#include "mesh/tri_mesh.h"

namespace facesr {

// Rigid jaw motion at full weight of one jaw blendshape: x' = R x + t.
struct JawShape {
  std::string name;
  Mat3 R = Mat3::Identity();
  Vec3 t = Vec3::Zero();
  double fit_rms_cm = 0;  // residual of the rigid fit to the lower teeth
};

struct Jaw {
  Vec3 pivot = Vec3::Zero();  // a point on the hinge axis (cm)
  Vec3 axis = Vec3::UnitX();  // unit hinge axis; positive angle opens the mouth
  double open_angle_deg = 0;  // hinge angle at jawOpen = 1
  double hinge_max_error_cm = 0;  // hinge (axis+angle) vs jawOpen lower teeth
  std::vector<JawShape> shapes;
};

enum class MuscleType : uint8_t { Line = 0, Sphincter = 1 };

struct Muscle {
  std::string name;
  MuscleType type = MuscleType::Line;
  Points curve;  // centre line through the muscle belly (closed for sphincters)
  double radius = 0;
};

// Barycentric location of a point in a tet mesh.
struct Embedding {
  std::vector<int32_t> tet;     // per point
  std::vector<float> weights;   // per point, 4 barycentric weights
  std::vector<uint8_t> outside;  // 1 if the point lay outside and was snapped to the nearest tet
};

// One volumetric simulation mesh (HR conforming, or LR lattice) with what the
// simulator needs on it.
struct SimMesh {
  TetMesh mesh;                      // rest pose (cm)
  std::vector<int32_t> muscle;       // per tet: dominant muscle, -1 if none
  std::vector<float> muscle_fraction;  // per tet: fraction of volume in that muscle
  std::vector<float> fibre;          // per tet: unit fibre direction (3 floats)
  std::vector<int32_t> dirichlet;    // nodes attached to bone
  std::vector<uint8_t> dirichlet_bone;  // 0 = cranium, 1 = jaw
  Embedding surface;                 // face surface vertices in this mesh
  std::vector<int32_t> tracks;       // face-surface vertex indices carrying track springs
  std::vector<float> track_area;     // skin area (cm²) each track represents
};

struct Lattice {
  Vec3 origin = Vec3::Zero();
  double cell = 0;  // cm
  std::array<int32_t, 3> dims{0, 0, 0};  // cells along x, y, z
};

// Mouth-opening pre-deformation of the LR rest pose (paper §4): the jaw
// region rotated by `angle_deg` about the jaw hinge with per-point weights.
struct Predeform {
  double angle_deg = 0;
  std::vector<float> surface_jaw_weight;  // per face-surface vertex
  Points surface_predeformed;             // face surface in the LR rest frame
};

// The immutable anatomical rig. Built once by rig_build(), saved as one
// versioned binary file, shared read-only by simulators and contexts.
struct Rig {
  std::string name;
  std::string units = "cm";
  // Output face surface.
  Points surface;  // rest positions
  Tris surface_tris;
  std::vector<int32_t> surface_source_vertex;  // index in the source mesh
  // Linear blendshape model on the face surface.
  std::vector<std::string> blendshape_names;
  std::vector<float> blendshape_deltas;  // [shape][vertex][3]
  std::vector<std::string> landmark_names;
  std::vector<int32_t> landmark_vertex;  // face-surface vertex
  Jaw jaw;
  std::vector<Muscle> muscles;
  // activation[b * muscles + m]: activation of muscle m per unit weight of blendshape b.
  std::vector<float> activation;
  TriMesh teeth_upper, teeth_lower;
  SimMesh hr, lr;
  Lattice lattice;
  Predeform predeform;
  // Build record.
  double build_seconds = 0;
  std::string source;

  int num_blendshapes() const { return int(blendshape_names.size()); }
  int num_surface_vertices() const { return int(surface.rows()); }
};

}  // namespace facesr
