#include "sr/sr_geometry_compare.h"

#include <algorithm>
#include <cmath>

namespace facesr {

namespace {

template <class T>
bool same_ints(const std::vector<T>& stored, const std::vector<T>& current) {
  return stored.empty() || stored == current;
}

double max_abs_difference(const std::vector<float>& stored, const std::vector<float>& current) {
  double worst = 0;
  for (size_t i = 0; i < stored.size(); ++i)
    worst = std::max(worst, std::abs(double(stored[i]) - double(current[i])));
  return worst;
}

}  // namespace

SrGeometryDifference compare_sr_geometry(const SrGeometry& stored, const SrGeometry& current) {
  SrGeometryDifference d;
  auto mismatch = [&](const char* what) {
    if (d.topology_mismatch.empty()) d.topology_mismatch = what;
  };
  if (stored.num_lr != current.num_lr) mismatch("num_lr");
  if (stored.num_hr != current.num_hr) mismatch("num_hr");
  if (stored.graph_k != current.graph_k) mismatch("graph_k");
  if (stored.upsample_k != current.upsample_k) mismatch("upsample_k");
  if (!same_ints(stored.lr_graph, current.lr_graph)) mismatch("lr_graph");
  if (!same_ints(stored.lr_to_hr, current.lr_to_hr)) mismatch("lr_to_hr");
  if (!same_ints(stored.up_index, current.up_index)) mismatch("up_index");
  if (!same_ints(stored.euclid_index, current.euclid_index)) mismatch("euclid_index");
  if (!same_ints(stored.hr_tris, current.hr_tris)) mismatch("hr_tris");
  if (!same_ints(stored.up_is_euclid, current.up_is_euclid)) mismatch("up_is_euclid");
  if (!same_ints(stored.embed_nodes, current.embed_nodes)) mismatch("embed_nodes");
  auto floats = [&](const char* what, const std::vector<float>& s, const std::vector<float>& c, double& worst) {
    if (s.empty()) return;
    if (s.size() != c.size()) {
      mismatch(what);
      return;
    }
    worst = std::max(worst, max_abs_difference(s, c));
  };
  floats("lr_rest", stored.lr_rest, current.lr_rest, d.max_position_cm);
  floats("hr_rest", stored.hr_rest, current.hr_rest, d.max_position_cm);
  floats("hr_rest_lr_frame", stored.hr_rest_lr_frame, current.hr_rest_lr_frame, d.max_position_cm);
  floats("up_dist", stored.up_dist, current.up_dist, d.max_distance_cm);
  floats("euclid_dist", stored.euclid_dist, current.euclid_dist, d.max_distance_cm);
  floats("embed_weights", stored.embed_weights, current.embed_weights, d.max_weight);
  return d;
}

}  // namespace facesr
