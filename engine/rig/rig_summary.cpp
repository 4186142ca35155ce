#include "rig/rig_summary.h"

#include <algorithm>

#include "mesh/tet_mesh.h"

namespace facesr {

namespace {

template <class T>
long count_equal(const std::vector<T>& v, T value) {
  return long(std::count(v.begin(), v.end(), value));
}

nlohmann::json muscle_tets_per_muscle(const Rig& rig, const SimMesh& s) {
  std::vector<long> n(rig.muscles.size(), 0);
  for (int32_t m : s.muscle)
    if (m >= 0 && size_t(m) < n.size()) n[size_t(m)]++;
  auto out = nlohmann::json::object();
  for (size_t m = 0; m < n.size(); ++m) out[rig.muscles[m].name] = n[m];
  return out;
}

nlohmann::json vec3(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

nlohmann::json rig_summary(const Rig& rig) {
  const TetQuality hq = tet_quality(rig.hr.mesh);
  const TetQuality lq = tet_quality(rig.lr.mesh);
  const long hr_tets = long(rig.hr.mesh.T.rows()), lr_tets = long(rig.lr.mesh.T.rows());
  // tet_quality reports min 180° for an empty mesh; 0 reads less like a result.
  auto min_dihedral = [](const TetQuality& q, long tets) {
    return tets ? q.min_dihedral_deg : 0.0;
  };

  nlohmann::json j;
  j["name"] = rig.name;
  j["source"] = rig.source;
  j["units"] = rig.units;
  j["build_seconds"] = rig.build_seconds;

  j["surface_vertices"] = rig.surface.rows();
  j["surface_triangles"] = rig.surface_tris.rows();
  j["hr_vertices"] = rig.hr.mesh.X.rows();
  j["hr_tets"] = hr_tets;
  j["lr_vertices"] = rig.lr.mesh.X.rows();
  j["lr_tets"] = lr_tets;
  j["hr_over_lr_tets"] = lr_tets ? double(hr_tets) / double(lr_tets) : 0.0;
  j["embedded_outside_hr"] = count_equal<uint8_t>(rig.hr.surface.outside, 1);
  j["embedded_outside_lr"] = count_equal<uint8_t>(rig.lr.surface.outside, 1);

  j["hr_min_dihedral_deg"] = min_dihedral(hq, hr_tets);
  j["hr_max_dihedral_deg"] = hq.max_dihedral_deg;
  j["lr_min_dihedral_deg"] = min_dihedral(lq, lr_tets);
  j["lr_max_dihedral_deg"] = lq.max_dihedral_deg;
  j["inverted_tets"] = hq.inverted + lq.inverted;
  j["hr_volume_cm3"] = hq.total_volume;
  j["lr_volume_cm3"] = lq.total_volume;

  auto names = nlohmann::json::array();
  for (const auto& m : rig.muscles) names.push_back(m.name);
  j["muscles"] = rig.muscles.size();
  j["muscle_names"] = names;
  j["muscle_tets_hr"] = long(rig.hr.muscle.size()) - count_equal<int32_t>(rig.hr.muscle, -1);
  j["muscle_tets_lr"] = long(rig.lr.muscle.size()) - count_equal<int32_t>(rig.lr.muscle, -1);
  j["muscle_tets_hr_per_muscle"] = muscle_tets_per_muscle(rig, rig.hr);
  j["muscle_tets_lr_per_muscle"] = muscle_tets_per_muscle(rig, rig.lr);

  j["dirichlet_nodes_hr"] = rig.hr.dirichlet.size();
  j["dirichlet_nodes_lr"] = rig.lr.dirichlet.size();
  j["dirichlet_jaw_nodes_hr"] = count_equal<uint8_t>(rig.hr.dirichlet_bone, 1);
  j["dirichlet_jaw_nodes_lr"] = count_equal<uint8_t>(rig.lr.dirichlet_bone, 1);
  j["tracks_hr"] = rig.hr.tracks.size();
  j["tracks_lr"] = rig.lr.tracks.size();

  j["blendshapes"] = rig.blendshape_names.size();
  j["blendshape_names"] = rig.blendshape_names;
  j["landmarks"] = rig.landmark_names.size();

  j["lattice_cell_cm"] = rig.lattice.cell;
  j["lattice_dims"] = rig.lattice.dims;
  j["predeform_angle_deg"] = rig.predeform.angle_deg;

  auto shapes = nlohmann::json::array();
  for (const auto& s : rig.jaw.shapes)
    shapes.push_back({{"name", s.name}, {"fit_rms_cm", s.fit_rms_cm}});
  j["jaw"] = {{"pivot", vec3(rig.jaw.pivot)},
              {"axis", vec3(rig.jaw.axis)},
              {"open_angle_deg", rig.jaw.open_angle_deg},
              {"hinge_max_error_cm", rig.jaw.hinge_max_error_cm},
              {"shapes", shapes}};
  return j;
}

}  // namespace facesr
