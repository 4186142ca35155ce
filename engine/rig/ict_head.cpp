#include "rig/ict_head.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/progress.h"
#include "mesh/obj_io.h"
#include "mesh/remesh.h"
#include "rig/landmarks.h"

namespace facesr {
namespace {

// FaceKit vertex ranges (inclusive), from the ICT-FaceKit documentation.
constexpr int kFaceEnd = 9408;
constexpr int kHeadEnd = 11247;
constexpr int kMouthEnd = 13293;
constexpr int kEyeSocketEnd = 14061;
constexpr int kUpperTeeth0 = 17039, kUpperTeeth1 = 19246;
constexpr int kLowerTeeth0 = 19247, kLowerTeeth1 = 21450;

TriMesh extract(const TriMesh& m, int v0, int v1) {
  std::vector<int> map(m.V.rows(), -1);
  TriMesh out;
  out.V.resize(v1 - v0 + 1, 3);
  for (int v = v0; v <= v1; ++v) {
    map[v] = v - v0;
    out.V.row(v - v0) = m.V.row(v);
  }
  std::vector<Vec3i> tris;
  for (int f = 0; f < m.F.rows(); ++f) {
    const int a = m.F(f, 0), b = m.F(f, 1), c = m.F(f, 2);
    if (map[a] >= 0 && map[b] >= 0 && map[c] >= 0) tris.emplace_back(map[a], map[b], map[c]);
  }
  out.F.resize(long(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t) out.F.row(long(t)) = tris[t].cast<int32_t>().transpose();
  return out;
}

}  // namespace

HeadSource load_ict_head(const std::string& folder, bool verbose) {
  namespace fs = std::filesystem;
  require(fs::is_directory(folder), "ICT source '" + folder + "' is not a folder");
  const std::string neutral_path = folder + "/generic_neutral_mesh.obj";
  const std::string json_path = folder + "/vertex_indices.json";
  require(fs::exists(neutral_path), "ICT source: missing '" + neutral_path + "'");
  require(fs::exists(json_path), "ICT source: missing '" + json_path + "'");
  const TriMesh full = read_obj(neutral_path);
  require(full.V.rows() > kLowerTeeth1, neutral_path + ": has " + std::to_string(full.V.rows()) +
                                             " vertices; the FaceKit layout needs at least " +
                                             std::to_string(kLowerTeeth1 + 1));
  nlohmann::json meta;
  try {
    std::ifstream in(json_path);
    meta = nlohmann::json::parse(in);
  } catch (const std::exception& e) {
    throw Error(json_path + ": malformed JSON (" + e.what() + ")");
  }
  require(meta.contains("expressions") && meta.contains("idx_to_landmark_verts"),
          json_path + ": missing 'expressions' or 'idx_to_landmark_verts'");

  HeadSource src;
  src.name = "ict-facekit";
  src.skin = extract(full, 0, kEyeSocketEnd);
  const int nskin = int(src.skin.V.rows());
  src.region.resize(nskin);
  for (int v = 0; v < nskin; ++v)
    src.region[v] = v <= kFaceEnd ? SkinRegion::Face
                    : v <= kHeadEnd ? SkinRegion::Head
                    : v <= kMouthEnd ? SkinRegion::Mouth
                                     : SkinRegion::EyeSocket;
  // Cap the neck cut: its loop is the only boundary of the skin surface.
  const auto loops = boundary_loops(src.skin.F);
  require(loops.size() == 1, neutral_path + ": expected the skin to have one hole (the neck cut), found " +
                                 std::to_string(loops.size()));
  const auto& loop = loops[0];
  Vec3 c = Vec3::Zero();
  for (int v : loop) c += src.skin.V.row(v).transpose();
  c /= double(loop.size());
  src.skin.V.conservativeResize(nskin + 1, 3);
  src.skin.V.row(nskin) = c.transpose();
  src.region.push_back(SkinRegion::NeckCap);
  const long nf = src.skin.F.rows();
  src.skin.F.conservativeResize(nf + long(loop.size()), 3);
  // The loop runs along boundary half-edges a->b of existing faces; the cap
  // face must use b->a to keep a consistent orientation.
  for (size_t k = 0; k < loop.size(); ++k)
    src.skin.F.row(nf + long(k)) << loop[(k + 1) % loop.size()], loop[k], nskin;
  for (int v = 0; v <= kFaceEnd; ++v) src.face_vertices.push_back(v);
  // The FaceKit lips overlap slightly at the mouth corners; TetGen needs a
  // surface without self-intersections.
  const RepairReport rep = repair_self_intersections(src.skin);
  if (verbose && rep.initial_pairs > 0)
    std::fprintf(stderr, "[rig] repaired %ld self-intersecting triangle pairs: moved %ld vertices by at most %.3f cm\n",
                 rep.initial_pairs, rep.moved, rep.max_displacement);

  src.teeth_upper = extract(full, kUpperTeeth0, kUpperTeeth1);
  src.teeth_lower = extract(full, kLowerTeeth0, kLowerTeeth1);

  const auto names = meta["expressions"].get<std::vector<std::string>>();
  Progress progress("rig: read blendshapes", long(names.size()), verbose);
  long done = 0;
  for (const auto& name : names) {
    const std::string path = folder + "/" + name + ".obj";
    require(fs::exists(path), "ICT source: missing blendshape '" + path + "'");
    const Points V = read_obj_vertices(path);
    require(V.rows() == full.V.rows(), path + ": has " + std::to_string(V.rows()) +
                                           " vertices but the neutral mesh has " +
                                           std::to_string(full.V.rows()) + " (different topology)");
    Points delta = Points::Zero(nskin + 1, 3);
    delta.topRows(nskin) = V.topRows(nskin) - full.V.topRows(nskin);
    src.blendshape_names.push_back(name);
    src.blendshape_deltas.push_back(std::move(delta));
    // The jaw shapes' rigid motion is fitted from the lower teeth later; keep
    // their teeth deltas in a side channel by storing the full mesh teeth.
    if (name.rfind("jaw", 0) == 0) {
      Points teeth = V.block(kLowerTeeth0, 0, kLowerTeeth1 - kLowerTeeth0 + 1, 3);
      src.jaw_shape_lower_teeth.emplace_back(name, std::move(teeth));
    }
    progress.update(++done, name);
  }
  progress.finish();
  const auto lm = meta["idx_to_landmark_verts"].get<std::vector<int>>();
  src.landmarks = landmarks_from_multipie68(lm, src.skin.V);
  return src;
}

}  // namespace facesr
