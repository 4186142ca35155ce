// facesr_gltf_check FILE.gltf [TARGETS]: the structural checks of the Khronos
// glTF validator that matter for the sample's output. The JSON parses, the
// embedded buffer decodes to its byteLength, every accessor fits its buffer
// view, POSITION accessors carry min/max equal to their data, base normals
// are unit, indices are in range, and the weight animation has one output per
// morph target per keyframe. Prints the first problem and exits 1.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

using nlohmann::json;

struct Problem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

void require(bool ok, const std::string& what) {
  if (!ok) throw Problem(what);
}

std::vector<uint8_t> decode_base64(const std::string& s) {
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    return -1;
  };
  require(s.size() % 4 == 0, "base64 length is not a multiple of 4");
  std::vector<uint8_t> out;
  out.reserve(s.size() / 4 * 3);
  for (size_t i = 0; i < s.size(); i += 4) {
    int v[4];
    int pad = 0;
    for (int k = 0; k < 4; ++k) {
      if (s[i + k] == '=' && i + 4 == s.size() && k >= 2) {
        v[k] = 0;
        ++pad;
      } else {
        require(pad == 0 && (v[k] = value(s[i + k])) >= 0, "bad base64 character");
      }
    }
    const uint32_t bits = uint32_t(v[0]) << 18 | uint32_t(v[1]) << 12 | uint32_t(v[2]) << 6 | uint32_t(v[3]);
    out.push_back(uint8_t(bits >> 16));
    if (pad < 2) out.push_back(uint8_t(bits >> 8));
    if (pad < 1) out.push_back(uint8_t(bits));
  }
  return out;
}

struct Gltf {
  json j;
  std::vector<uint8_t> buffer;

  // Accessor `a`'s elements as floats (or uint32 cast to double), after
  // checking that it fits its buffer view.
  std::vector<double> read(int a, int& components) const {
    const json& acc = j.at("accessors").at(size_t(a));
    const std::string type = acc.at("type");
    components = type == "SCALAR" ? 1 : type == "VEC3" ? 3 : 0;
    require(components > 0, "accessor " + std::to_string(a) + ": unexpected type " + type);
    const int ct = acc.at("componentType");
    require(ct == 5126 || ct == 5125, "accessor " + std::to_string(a) + ": unexpected componentType");
    const size_t count = acc.at("count");
    require(count > 0, "accessor " + std::to_string(a) + ": count is 0");
    const json& view = j.at("bufferViews").at(size_t(acc.at("bufferView")));
    require(view.at("buffer") == 0, "buffer view of accessor " + std::to_string(a) + " is not buffer 0");
    const size_t view_offset = view.value("byteOffset", 0), view_len = view.at("byteLength");
    const size_t offset = acc.value("byteOffset", 0);
    require(view_offset + view_len <= buffer.size(), "buffer view of accessor " + std::to_string(a) + " overruns");
    require(offset + count * components * 4 <= view_len,
            "accessor " + std::to_string(a) + ": " + std::to_string(count) + " elements do not fit its view");
    require((view_offset + offset) % 4 == 0, "accessor " + std::to_string(a) + " is not 4-byte aligned");
    std::vector<double> out(count * size_t(components));
    const uint8_t* p = buffer.data() + view_offset + offset;
    for (size_t i = 0; i < out.size(); ++i) {
      if (ct == 5126) {
        float f;
        std::memcpy(&f, p + 4 * i, 4);
        require(std::isfinite(f), "accessor " + std::to_string(a) + " has a non-finite value");
        out[i] = f;
      } else {
        uint32_t u;
        std::memcpy(&u, p + 4 * i, 4);
        out[i] = u;
      }
    }
    return out;
  }

  // min and max must be present and equal to the data's, per component.
  void check_bounds(int a) const {
    int c;
    const std::vector<double> v = read(a, c);
    const json& acc = j.at("accessors").at(size_t(a));
    require(acc.contains("min") && acc.contains("max"), "accessor " + std::to_string(a) + " has no min/max");
    require(acc["min"].size() == size_t(c) && acc["max"].size() == size_t(c),
            "accessor " + std::to_string(a) + ": min/max have the wrong length");
    for (int k = 0; k < c; ++k) {
      double lo = INFINITY, hi = -INFINITY;
      for (size_t i = size_t(k); i < v.size(); i += size_t(c)) lo = std::min(lo, v[i]), hi = std::max(hi, v[i]);
      require(float(acc["min"][size_t(k)].get<double>()) == float(lo) &&
                  float(acc["max"][size_t(k)].get<double>()) == float(hi),
              "accessor " + std::to_string(a) + ": min/max differ from the data");
    }
  }
};

void check(const std::string& path, int expected_targets) {
  std::ifstream in(path, std::ios::binary);
  require(in.good(), "cannot open " + path);
  std::stringstream ss;
  ss << in.rdbuf();
  Gltf g;
  try {
    g.j = json::parse(ss.str());
  } catch (const json::exception& e) {
    throw Problem(std::string("not valid JSON: ") + e.what());
  }
  const json& j = g.j;
  require(j.at("asset").at("version") == "2.0", "asset.version is not 2.0");
  require(j.at("buffers").size() == 1, "expected one buffer");
  const std::string uri = j["buffers"][0].at("uri");
  const std::string prefix = "data:application/octet-stream;base64,";
  require(uri.compare(0, prefix.size(), prefix) == 0, "the buffer is not an embedded base64 data URI");
  g.buffer = decode_base64(uri.substr(prefix.size()));
  require(g.buffer.size() == j["buffers"][0].at("byteLength").get<size_t>(), "buffer byteLength differs from data");

  const json& prim = j.at("meshes").at(0).at("primitives").at(0);
  int c;
  const int pos = prim.at("attributes").at("POSITION"), nrm = prim.at("attributes").at("NORMAL");
  const std::vector<double> p = g.read(pos, c), n = g.read(nrm, c);
  const size_t vertices = p.size() / 3;
  require(n.size() == p.size(), "NORMAL and POSITION counts differ");
  g.check_bounds(pos);
  for (size_t i = 0; i < vertices; ++i) {
    const double len = std::sqrt(n[3 * i] * n[3 * i] + n[3 * i + 1] * n[3 * i + 1] + n[3 * i + 2] * n[3 * i + 2]);
    require(std::fabs(len - 1) < 1e-3, "normal " + std::to_string(i) + " is not unit length");
  }
  const std::vector<double> idx = g.read(prim.at("indices"), c);
  require(idx.size() % 3 == 0, "index count is not a multiple of 3");
  for (double i : idx) require(i < double(vertices), "an index is out of range");

  const json& targets = prim.at("targets");
  require(expected_targets < 0 || int(targets.size()) == expected_targets,
          std::to_string(targets.size()) + " morph targets, expected " + std::to_string(expected_targets));
  for (const json& t : targets) {
    require(g.read(t.at("POSITION"), c).size() == p.size(), "a morph target's POSITION count differs");
    require(g.read(t.at("NORMAL"), c).size() == p.size(), "a morph target's NORMAL count differs");
    g.check_bounds(t.at("POSITION"));
  }

  const json& sampler = j.at("animations").at(0).at("samplers").at(0);
  const std::vector<double> times = g.read(sampler.at("input"), c);
  g.check_bounds(sampler.at("input"));
  for (size_t i = 1; i < times.size(); ++i) require(times[i] > times[i - 1], "keyframe times do not increase");
  require(g.read(sampler.at("output"), c).size() == times.size() * targets.size(),
          "the weight animation needs one value per morph target per keyframe");
  const json& target = j["animations"][0].at("channels").at(0).at("target");
  require(target.at("path") == "weights" && target.at("node") == 0, "the animation does not drive node 0's weights");
  std::printf("%s: valid (%zu vertices, %zu triangles, %zu morph targets, %zu keyframes)\n", path.c_str(), vertices,
              idx.size() / 3, targets.size(), times.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: facesr_gltf_check FILE.gltf [TARGETS]\n");
    return 2;
  }
  try {
    check(argv[1], argc == 3 ? std::atoi(argv[2]) : -1);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", argv[1], e.what());
    return 1;
  }
  return 0;
}
