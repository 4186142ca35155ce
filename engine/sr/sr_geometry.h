#pragma once
// Rest-pose neighbourhoods of the super-resolution network (paper §3.1,
// §3.2) and of the RBF and MLS baselines (appendix A.2, A.3). They depend
// only on the rig, so they are computed once and stored in the model file;
// training, evaluation and the runtime all read the same arrays.
#include <cstdint>
#include <string>
#include <vector>

#include "rig/rig.h"

namespace facesr {

struct SrGeometryOptions {
  int graph_k = 5;      // neighbours in the first EdgeConv graph (paper: 5)
  int upsample_k = 20;  // interpolation neighbours per HR vertex (paper: 20)
};

struct SrGeometry {
  int num_lr = 0;  // N: LR lattice nodes
  int num_hr = 0;  // M: HR face-surface vertices (the rig's surface)
  int graph_k = 0, upsample_k = 0;
  std::vector<float> lr_rest;  // N × 3, cm, the LR rest pose (lip-separating predeformed frame)
  std::vector<float> hr_rest;  // M × 3, cm, the rig's rest surface

  // §3.1: per LR node its graph_k nearest other LR nodes by shortest path
  // along the LR tet mesh's edges (rest lengths), nearest first.
  std::vector<int32_t> lr_graph;  // N × graph_k

  // §3.2: the LR node → HR surface vertex map of the one-to-one assignment
  // with the least total Euclidean distance (rest poses); -1 for the nodes
  // left over when N > M.
  std::vector<int32_t> lr_to_hr;  // N

  // §3.2: per HR vertex its upsample_k nearest mapped LR nodes by shortest
  // path over the HR surface's edges from the vertex to the node's mapped
  // vertex, nearest first, with that distance in cm.
  std::vector<int32_t> up_index;  // M × upsample_k
  std::vector<float> up_dist;     // M × upsample_k, cm

  // Ablation "without coordinate-based upsampling" (§5.4.1): per HR vertex
  // its upsample_k Euclidean-nearest LR nodes (rest poses), nearest first.
  std::vector<int32_t> euclid_index;  // M × upsample_k
  std::vector<float> euclid_dist;     // M × upsample_k, cm

  // Optional extras (empty when a stored model leaves them out):
  // The rig surface in the LR rest frame (rig.predeform.surface_predeformed,
  // or hr_rest when the rig has none). LR nodes and HR vertices are only
  // comparable within one frame, so the assignment, the Euclidean neighbours,
  // the Euclidean fill-ins and the MLS basis use these positions, while
  // geodesic distances are measured over hr_rest.
  std::vector<float> hr_rest_lr_frame;  // M × 3, cm
  std::vector<int32_t> hr_tris;         // T × 3, the rig's surface triangles (RBF geodesics)
  std::vector<uint8_t> up_is_euclid;    // M × upsample_k: 1 where a slot is a Euclidean fill-in

  // The face surface's barycentric embedding in the LR lattice (the
  // "embedded" baseline, Σ_k w_jk Δx^L_n(j,k)), for the network's optional
  // embedded skip connection.
  std::vector<int32_t> embed_nodes;   // M × 4 LR nodes
  std::vector<float> embed_weights;   // M × 4 barycentric weights

  // The positional-encoding index of each LR node (§3.1 encodes the node
  // index). Empty: the node's own index. A model carried over from another
  // rig (`facesr model transfer`) sets it to the index of the old rig's
  // corresponding node, so each region of the face keeps the encoding its
  // weights were trained with.
  std::vector<int32_t> pe_rows;  // N
};

// Fill-ins: the HR surface may have several connected components. Where a
// vertex's component holds fewer than upsample_k mapped vertices, the
// remaining slots take the Euclidean-nearest LR nodes not yet chosen, with
// their Euclidean distance, and the row is then sorted by distance. The LR
// graph is completed the same way for a node whose tet-mesh component has
// fewer than graph_k + 1 nodes.

// Throws Error when the rig has no LR nodes or surface, or k is out of range
// (graph_k in [1, N - 1], upsample_k in [1, min(N, 64)]).
SrGeometry build_sr_geometry(const Rig& rig, const SrGeometryOptions& opt = {});

// Checks sizes and index ranges of every array (of a loaded model, say);
// throws Error naming the first inconsistent field. `what` prefixes messages.
void validate_sr_geometry(const SrGeometry& g, const std::string& what = "sr geometry");

}  // namespace facesr
