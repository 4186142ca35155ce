#pragma once
// Collision handling for the HR reference simulation (paper §4: the HR
// simulation resolves lip–lip and lip–teeth contact; the LR one does not).
// Embree scenes: one refitted every Newton iteration over the deforming skin of
// the mouth region (lips and mouth lining, HR boundary faces), one static
// scene each for the upper teeth (cranium) and the lower teeth (queried in the
// jaw's frame). Detection finds, for every free mouth-region node, the deepest
// penetration into the opposite lip or into a tooth and returns it as a
// penalty plane (sim/contact.h) that the Newton solve then resolves.
#include <memory>
#include <string>
#include <vector>

#include "collide/deforming_scene.h"
#include "rig/rig.h"
#include "sim/contact.h"
#include "sim/sim_model.h"

namespace facesr {

struct CollisionOptions {
  bool self = true;   // lip–lip (skin against skin in the mouth region)
  bool teeth = true;  // skin against upper and lower teeth
  // Penalty stiffness per unit of skin area: k_node = stiffness · area(node),
  // kPa/cm (600× the default track-spring stiffness, so a track pulling a lip
  // 1 cm into the other lip is held back with ~0.002 cm of penetration).
  double stiffness = 3000;
  // Deepest penetration that is still recognised as contact, cm; points
  // further behind a surface are taken to be on its far side.
  double max_depth_cm = 0.6;
  // Nodes closer than this to an obstacle (cm) get a plane too; it only acts
  // once they cross it, and keeps the contact set stable between iterations.
  double margin_cm = 0.02;
  // Radius around the mouth centre (mean of the outer lip contour landmarks),
  // as a multiple of the mouth width (corner to corner).
  double region_scale = 0.8;
  // Triangles within this many edge rings of a node are its own neighbourhood,
  // never an obstacle for it.
  int exclude_rings = 3;
};

struct CollisionInfo {
  int region_nodes = 0;
  int region_triangles = 0;
  int rest_excluded = 0;  // nodes already behind an obstacle in the rest pose (ignored)
  bool teeth_closed = false;  // teeth meshes are watertight: inside tests by ray parity
  double mouth_width_cm = 0;
};

// ContactPlane::kind values.
enum ContactKind : int { kLipSelf = 0, kUpperTeeth = 1, kLowerTeeth = 2 };

class MouthCollider final : public ContactSource {
 public:
  // `model` must be the HR simulation model of `rig`.
  MouthCollider(const Rig& rig, const SimModel& model, const CollisionOptions& opt = {});
  ~MouthCollider() override;
  void detect(const std::vector<double>& x, const FrameInputs& in, std::vector<ContactPlane>& out) override;
  const CollisionInfo& info() const { return info_; }
  const std::vector<int>& region_nodes() const { return region_; }
  struct Teeth;  // a rigid obstacle's scene (mouth_collider.cpp)

 private:
  void find(const std::vector<double>& x, const FrameInputs& in, std::vector<ContactPlane>& out) const;

  CollisionOptions opt_;
  CollisionInfo info_;
  int num_nodes_ = 0;
  std::vector<int> region_;            // mouth-region nodes
  std::vector<uint8_t> region_free_;   // per region node: not bone, not excluded
  std::vector<double> k_;              // per region node, kPa·cm
  std::vector<std::vector<int>> own_;  // per region node: sorted triangles of its neighbourhood
  std::vector<std::vector<int>> node_tris_;  // per region node: incident region triangles
  std::unique_ptr<DeformingScene> skin_;
  std::unique_ptr<Teeth> upper_, lower_;
};

}  // namespace facesr
