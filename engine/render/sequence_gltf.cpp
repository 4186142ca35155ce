#include "render/sequence_gltf.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"
#include "render/mesh_raster.h"

namespace facesr {
namespace {

// glTF enums.
constexpr int kFloat = 5126, kUnsignedInt = 5125;
constexpr int kArrayBuffer = 34962, kElementArrayBuffer = 34963;
constexpr int kTriangles = 4;

// One binary buffer plus the bufferViews and accessors that describe it.
class GltfBuffer {
 public:
  // Appends `count` elements of `type` ("SCALAR", "VEC3") and returns the accessor index.
  int add(const void* data, size_t count, int components, int component_type, const char* type, int target,
          bool with_min_max) {
    const size_t bytes = count * components * 4;  // both component types used here are 4 bytes
    const size_t offset = bytes_.size();
    bytes_.resize(offset + bytes);
    std::memcpy(bytes_.data() + offset, data, bytes);
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", bytes}};
    if (target) view["target"] = target;
    views_.push_back(view);
    nlohmann::json acc = {
        {"bufferView", int(views_.size()) - 1}, {"componentType", component_type}, {"count", count}, {"type", type}};
    if (with_min_max) {  // required on POSITION attributes and animation inputs
      std::vector<double> lo(components, std::numeric_limits<double>::infinity()), hi(components, -lo[0]);
      const float* f = static_cast<const float*>(data);
      for (size_t i = 0; i < count; ++i)
        for (int k = 0; k < components; ++k) {
          lo[k] = std::min(lo[k], double(f[i * components + k]));
          hi[k] = std::max(hi[k], double(f[i * components + k]));
        }
      acc["min"] = lo;
      acc["max"] = hi;
    }
    accessors_.push_back(acc);
    return int(accessors_.size()) - 1;
  }
  const std::vector<uint8_t>& bytes() const { return bytes_; }
  const nlohmann::json& views() const { return views_; }
  const nlohmann::json& accessors() const { return accessors_; }

 private:
  std::vector<uint8_t> bytes_;
  nlohmann::json views_ = nlohmann::json::array(), accessors_ = nlohmann::json::array();
};

std::vector<int> checked_frames(const Rig& rig, const Sequence& seq, const std::vector<int>& chosen,
                                const std::string& path) {
  const std::string who = path + ": ";
  const int S = rig.num_surface_vertices(), F = seq.frames();
  require(S > 0 && rig.surface_tris.rows() > 0, who + "rig '" + rig.name + "' has an empty face surface");
  require(seq.header.num_surface == uint64_t(S) && seq.surface.size() == size_t(F) * S * 3,
          who + "the sequence has " + std::to_string(seq.header.num_surface) + " surface vertices but rig '" +
              rig.name + "' has " + std::to_string(S));
  std::vector<int> frames = chosen;
  if (frames.empty())
    for (int f = 0; f < F; ++f) frames.push_back(f);
  require(!frames.empty(), who + "the sequence has no frames");
  require(frames.size() <= size_t(kMaxGltfFrames),
          who + std::to_string(frames.size()) + " frames, more than the " + std::to_string(kMaxGltfFrames) +
              " a glTF export holds (one morph target each); choose fewer frames");
  for (size_t i = 0; i < frames.size(); ++i) {
    require(frames[i] >= 0 && frames[i] < F, who + "frame " + std::to_string(frames[i]) +
                                                 " is out of range (the sequence has " + std::to_string(F) +
                                                 " frames)");
    require(i == 0 || frames[i] > frames[i - 1], who + "frames must be in increasing order (animation time)");
  }
  return frames;
}

}  // namespace

std::string base64_encode(const void* data, size_t size) {
  static const char* abc = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const auto* p = static_cast<const uint8_t*>(data);
  std::string out;
  out.reserve((size + 2) / 3 * 4);
  for (size_t i = 0; i < size; i += 3) {
    const uint32_t b0 = p[i], b1 = i + 1 < size ? p[i + 1] : 0, b2 = i + 2 < size ? p[i + 2] : 0;
    const uint32_t v = (b0 << 16) | (b1 << 8) | b2;
    out += abc[(v >> 18) & 63];
    out += abc[(v >> 12) & 63];
    out += i + 1 < size ? abc[(v >> 6) & 63] : '=';
    out += i + 2 < size ? abc[v & 63] : '=';
  }
  return out;
}

void write_sequence_gltf(const Rig& rig, const Sequence& seq, const std::string& path, const std::vector<int>& chosen) {
  const std::vector<int> frames = checked_frames(rig, seq, chosen, path);
  const int S = rig.num_surface_vertices(), K = int(frames.size());
  const float* base = seq.frame_surface(frames[0]);

  GltfBuffer buf;
  std::vector<uint32_t> idx(size_t(rig.surface_tris.rows()) * 3);
  for (int t = 0; t < rig.surface_tris.rows(); ++t)
    for (int k = 0; k < 3; ++k) idx[size_t(t) * 3 + k] = uint32_t(rig.surface_tris(t, k));
  const int indices = buf.add(idx.data(), idx.size(), 1, kUnsignedInt, "SCALAR", kElementArrayBuffer, false);
  const int position = buf.add(base, S, 3, kFloat, "VEC3", kArrayBuffer, true);
  std::vector<float> normals;
  for (const Vec3& n : vertex_normals_xyz(base, S, rig.surface_tris))
    for (int k = 0; k < 3; ++k) normals.push_back(float(n[k]));
  const int normal = buf.add(normals.data(), S, 3, kFloat, "VEC3", kArrayBuffer, false);

  nlohmann::json primitive = {
      {"attributes", {{"POSITION", position}, {"NORMAL", normal}}}, {"indices", indices}, {"mode", kTriangles}};
  nlohmann::json mesh = {{"name", "face"}};
  nlohmann::json root;
  if (K > 1) {
    nlohmann::json targets = nlohmann::json::array();
    std::vector<float> offset(size_t(S) * 3);
    for (int k = 1; k < K; ++k) {
      const float* x = seq.frame_surface(frames[k]);
      for (size_t i = 0; i < offset.size(); ++i) offset[i] = x[i] - base[i];
      targets.push_back({{"POSITION", buf.add(offset.data(), S, 3, kFloat, "VEC3", kArrayBuffer, true)}});
    }
    primitive["targets"] = targets;
    mesh["weights"] = std::vector<float>(K - 1, 0.0f);
    // Frame k shows target k-1 alone; the first frame is the base mesh (all weights 0).
    std::vector<float> times(K), weights(size_t(K) * (K - 1), 0.0f);
    for (int k = 0; k < K; ++k) {
      times[k] = float(seq.time[frames[k]] - seq.time[frames[0]]);
      if (k > 0) weights[size_t(k) * (K - 1) + (k - 1)] = 1.0f;
    }
    const int input = buf.add(times.data(), K, 1, kFloat, "SCALAR", 0, true);
    const int output = buf.add(weights.data(), weights.size(), 1, kFloat, "SCALAR", 0, false);
    const nlohmann::json sampler = {{"input", input}, {"output", output}, {"interpolation", "STEP"}};
    const nlohmann::json channel = {{"sampler", 0}, {"target", {{"node", 0}, {"path", "weights"}}}};
    const nlohmann::json animation = {{"name", "sequence"},
                                      {"samplers", nlohmann::json::array({sampler})},
                                      {"channels", nlohmann::json::array({channel})}};
    root["animations"] = nlohmann::json::array({animation});
  }
  mesh["primitives"] = nlohmann::json::array({primitive});

  root["asset"] = {{"version", "2.0"},
                   {"generator", "facesr"},
                   {"extras",
                    {{"units", "cm"},
                     {"note", "positions in cm; the node's scale 0.01 converts them to glTF metres"},
                     {"rig", rig.name},
                     {"resolution", seq.header.resolution},
                     {"fps", seq.header.fps},
                     {"frames", frames}}}};
  root["scene"] = 0;
  root["scenes"] = nlohmann::json::array({{{"nodes", nlohmann::json::array({0})}}});
  nlohmann::json node = {{"name", rig.name.empty() ? std::string("face") : rig.name},
                         {"mesh", 0},
                         {"scale", nlohmann::json::array({0.01, 0.01, 0.01})}};
  root["nodes"] = nlohmann::json::array({node});
  root["meshes"] = nlohmann::json::array({mesh});
  nlohmann::json buffer = {
      {"byteLength", buf.bytes().size()},
      {"uri", "data:application/octet-stream;base64," + base64_encode(buf.bytes().data(), buf.bytes().size())}};
  root["buffers"] = nlohmann::json::array({buffer});
  root["bufferViews"] = buf.views();
  root["accessors"] = buf.accessors();
  const std::string text = root.dump();
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace facesr
