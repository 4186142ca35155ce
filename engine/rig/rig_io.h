#pragma once
#include <cstdint>
#include <string>

#include "rig/rig.h"

// Rig file format, version 1 (all integers and floats little-endian):
//
//   offset  size  field
//   0       8     magic "FACESRIG"
//   8       4     u32 format version (= 1)
//   12      4     u32 flags (reserved, 0)
//   16      8     u64 payload size P
//   24      P     payload
//   24+P    8     u64 FNV-1a 64 checksum of the payload bytes
//
// Nothing may follow the checksum. The payload holds every Rig field in this
// order, using these encodings:
//   string       u64 length, bytes
//   vector<T>    u64 count, count * sizeof(T) bytes
//   string list  u64 count, strings
//   matrix       u64 rows, u64 cols, rows*cols elements row-major
//                (Points: f64 N×3, Tris: i32 N×3, Tets: i32 N×4)
//   Vec3 / Mat3  3 / 9 f64 (Mat3 row-major)
//   TriMesh      V, F
//   TetMesh      X, T
//   Embedding    tet (vector<i32>), weights (vector<f32>), outside (vector<u8>)
//   SimMesh      mesh, muscle (i32), muscle_fraction (f32), fibre (f32),
//                dirichlet (i32), dirichlet_bone (u8), surface, tracks (i32),
//                track_area (f32)
//
//   Rig: name, units, surface, surface_tris, surface_source_vertex (i32),
//        blendshape_names, blendshape_deltas (f32), landmark_names,
//        landmark_vertex (i32),
//        jaw: pivot, axis, open_angle_deg f64, hinge_max_error_cm f64,
//             u64 shape count, per shape: name, R, t, fit_rms_cm f64
//        muscles: u64 count, per muscle: name, type u8, curve, radius f64
//        activation (f32), teeth_upper, teeth_lower, hr, lr,
//        lattice: origin, cell f64, dims 3 × i32
//        predeform: angle_deg f64, surface_jaw_weight (f32), surface_predeformed
//        build_seconds f64, source
//
// Any change to this layout or to the Rig struct needs a new format version.

namespace facesr {

// Checks the rig's internal consistency (array sizes, index ranges, finite
// values). Throws Error "<context>: <field> ..." on the first problem.
void validate_rig(const Rig& rig, const std::string& context);

// Validates, then writes atomically: on failure no file (and no partial file)
// is left at `path`.
void save_rig(const Rig& rig, const std::string& path);

// Reads and fully validates a rig file; every Error names `path`.
Rig load_rig(const std::string& path);

// FNV-1a 64 of the serialized payload: identifies the exact rig a trained
// model belongs to. The build record (build_seconds, source) is not part of
// it: the rig builder is deterministic, so a rebuilt rig keeps its checksum.
uint64_t rig_checksum(const Rig& rig);

}  // namespace facesr
