#include "tiny_files.h"

#include "rig/rig_io.h"

namespace facesr::tiny {

namespace {

// Two positively oriented tets sharing the face (1, 2, 3); volumes 1/6 and 1/3.
TetMesh two_tets() {
  TetMesh m;
  m.X.resize(5, 3);
  m.X << 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1;
  m.T.resize(2, 4);
  m.T << 0, 1, 2, 3, 1, 2, 3, 4;
  return m;
}

}  // namespace

Rig rig() {
  Rig r;
  r.name = "tiny";
  r.source = "synthetic";
  r.build_seconds = 1.25;

  r.surface.resize(4, 3);
  r.surface << 0.1, 0.1, 0.1, 0.5, 0.2, 0.1, 0.2, 0.5, 0.1, 0.6, 0.6, 0.6;
  r.surface_tris.resize(2, 3);
  r.surface_tris << 0, 1, 2, 1, 3, 2;
  r.surface_source_vertex = {10, 11, 12, 13};

  r.blendshape_names = {"jawOpen", "smile"};
  for (int i = 0; i < 2 * 4 * 3; ++i) r.blendshape_deltas.push_back(0.01f * float(i));
  r.landmark_names = {"chin", "nose"};
  r.landmark_vertex = {0, 3};

  r.jaw.pivot = Vec3(0.1, -0.2, 0.3);
  r.jaw.axis = Vec3(1, 0, 0);
  r.jaw.open_angle_deg = 18.5;
  r.jaw.hinge_max_error_cm = 0.02;
  JawShape js;
  js.name = "jawOpen";
  js.R << 1, 0, 0, 0, 0.9, -0.1, 0, 0.1, 0.9;  // asymmetric: catches transposed storage
  js.t = Vec3(0, -0.5, 0.1);
  js.fit_rms_cm = 0.003;
  r.jaw.shapes = {js};

  Muscle mu;
  mu.name = "zygomaticus";
  mu.type = MuscleType::Sphincter;
  mu.curve.resize(2, 3);
  mu.curve << 0, 0, 0, 1, 1, 1;
  mu.radius = 0.4;
  r.muscles = {mu};
  r.activation = {0.0f, 0.75f};

  r.teeth_upper.V.resize(3, 3);
  r.teeth_upper.V << 0, 0, 0, 1, 0, 0, 0, 1, 0;
  r.teeth_upper.F.resize(1, 3);
  r.teeth_upper.F << 0, 1, 2;
  r.teeth_lower.V = r.teeth_upper.V.array() - 0.5;
  r.teeth_lower.F = r.teeth_upper.F;

  r.hr.mesh = two_tets();
  r.hr.muscle = {0, -1};
  r.hr.muscle_fraction = {0.8f, 0.0f};
  r.hr.fibre = {1, 0, 0, 0, 1, 0};
  r.hr.dirichlet = {0, 4, 2};
  r.hr.dirichlet_bone = {0, 1, 1};
  r.hr.surface.tet = {0, 0, 1, 1};
  r.hr.surface.weights = {0.25f, 0.25f, 0.25f, 0.25f, 0.1f, 0.2f, 0.3f, 0.4f,
                          0.4f,  0.3f,  0.2f,  0.1f,  0.0f, 0.0f, 0.5f, 0.5f};
  r.hr.surface.outside = {0, 0, 0, 1};
  r.hr.tracks = {0, 3};
  r.hr.track_area = {0.5f, 0.25f};

  r.lr.mesh.X = r.hr.mesh.X.topRows(4);
  r.lr.mesh.T = r.hr.mesh.T.topRows(1);
  r.lr.muscle = {0};
  r.lr.muscle_fraction = {0.5f};
  r.lr.fibre = {0, 0, 1};
  r.lr.dirichlet = {1};
  r.lr.dirichlet_bone = {1};
  r.lr.surface.tet = {0, 0, 0, 0};
  r.lr.surface.weights = r.hr.surface.weights;
  r.lr.surface.outside = {1, 0, 1, 0};
  r.lr.tracks = {2};
  r.lr.track_area = {1.5f};

  r.lattice.origin = Vec3(-1, -2, -3);
  r.lattice.cell = 0.75;
  r.lattice.dims = {4, 5, 6};

  r.predeform.angle_deg = 12;
  r.predeform.surface_jaw_weight = {0.0f, 0.5f, 1.0f, 0.25f};
  r.predeform.surface_predeformed = r.surface.array() + 0.01;
  return r;
}

DatasetHeader dataset_header() {
  static const DatasetHeader h = [] {
    const Rig r = rig();
    DatasetHeader d;
    d.name = "tiny";
    d.rig_checksum = rig_checksum(r);
    d.fps = 30;
    d.num_lr_nodes = uint64_t(r.lr.mesh.X.rows());
    d.num_surface = uint64_t(r.surface.rows());
    d.weight_names = r.blendshape_names;
    return d;
  }();
  return h;
}

}  // namespace facesr::tiny
