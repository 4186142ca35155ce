#include "rig/identity_head.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/atomic_file.h"
#include "core/error.h"

namespace facesr {
namespace {

namespace fs = std::filesystem;

// An OBJ file as its lines, with the "v" lines' positions parsed. The other
// lines (texture coordinates, faces, comments) are carried through verbatim
// so the written head keeps the FaceKit's UVs and topology.
struct ObjText {
  std::vector<std::string> lines;
  std::vector<size_t> v_line;   // index into lines of each vertex
  std::vector<double> v;        // vertex × 3
};

ObjText read_obj_text(const std::string& path) {
  std::ifstream in(path);
  require(bool(in), "cannot open '" + path + "'");
  ObjText o;
  std::string line;
  while (std::getline(in, line)) {
    if (line.size() > 2 && line[0] == 'v' && line[1] == ' ') {
      const char* s = line.c_str() + 2;
      char* end = nullptr;
      for (int c = 0; c < 3; ++c) {
        const double x = std::strtod(s, &end);
        require(end != s && std::isfinite(x), path + ": line " + std::to_string(o.lines.size() + 1) +
                                                  ": malformed vertex '" + line.substr(0, 60) + "'");
        o.v.push_back(x);
        s = end;
      }
      o.v_line.push_back(o.lines.size());
    }
    o.lines.push_back(std::move(line));
  }
  require(!o.v_line.empty(), path + ": no vertices");
  return o;
}

std::string mode_path(const std::string& dir, int k) {
  char name[32];
  std::snprintf(name, sizeof(name), "identity%03d.obj", k);
  return dir + "/" + name;
}

void write_obj_text(const std::string& path, ObjText& o, const std::vector<double>& v) {
  char buf[96];
  for (size_t i = 0; i < o.v_line.size(); ++i) {
    std::snprintf(buf, sizeof(buf), "v %.6f %.6f %.6f", v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    o.lines[o.v_line[i]] = buf;
  }
  write_file_atomically(path, [&](std::ostream& out) {
    for (const auto& l : o.lines) out << l << '\n';
  });
}

}  // namespace

int count_identity_modes(const std::string& dir) {
  int k = 0;
  while (fs::exists(mode_path(dir, k))) ++k;
  return k;
}

std::vector<double> random_identity_weights(uint32_t seed, int modes, double max_sigma) {
  require(modes >= 0, "random_identity_weights: negative mode count");
  require(max_sigma >= 0 && std::isfinite(max_sigma), "random_identity_weights: max_sigma must be ≥ 0");
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-max_sigma, max_sigma);
  std::vector<double> w(modes);
  for (double& x : w) x = u(rng);
  return w;
}

IdentityHeadReport write_identity_head(const IdentityHeadSpec& spec, const std::string& out_dir) {
  require(fs::is_directory(spec.ict_dir), "ICT folder '" + spec.ict_dir + "' is not a folder");
  require(fs::is_directory(spec.identities_dir), "identity folder '" + spec.identities_dir + "' is not a folder");
  const int available = count_identity_modes(spec.identities_dir);
  require(int(spec.weights.size()) <= available,
          std::to_string(spec.weights.size()) + " identity weights given but '" + spec.identities_dir + "' has " +
              std::to_string(available) + " modes");
  for (size_t k = 0; k < spec.weights.size(); ++k)
    require(std::isfinite(spec.weights[k]), "identity weight " + std::to_string(k) + " is not finite");
  const std::string neutral_path = spec.ict_dir + "/generic_neutral_mesh.obj";
  const std::string meta_path = spec.ict_dir + "/vertex_indices.json";
  require(fs::exists(neutral_path), "ICT folder: missing '" + neutral_path + "'");
  require(fs::exists(meta_path), "ICT folder: missing '" + meta_path + "'");
  std::vector<std::string> names;
  try {
    std::ifstream in(meta_path);
    names = nlohmann::json::parse(in).at("expressions").get<std::vector<std::string>>();
  } catch (const std::exception& e) {
    throw Error(meta_path + ": malformed or without 'expressions' (" + e.what() + ")");
  }

  // Read and check everything before the first write.
  ObjText generic = read_obj_text(neutral_path);
  const size_t n = generic.v.size();
  const auto same_size = [&](const ObjText& o, const std::string& path) {
    require(o.v.size() == n, path + ": has " + std::to_string(o.v.size() / 3) + " vertices but '" + neutral_path +
                                 "' has " + std::to_string(n / 3));
  };
  std::vector<double> neutral = generic.v;
  for (size_t k = 0; k < spec.weights.size(); ++k) {
    const std::string p = mode_path(spec.identities_dir, int(k));
    const ObjText mode = read_obj_text(p);
    same_size(mode, p);
    for (size_t i = 0; i < n; ++i) neutral[i] += spec.weights[k] * (mode.v[i] - generic.v[i]);
  }
  for (const auto& name : names)
    require(fs::exists(spec.ict_dir + "/" + name + ".obj"), "ICT folder: missing blendshape '" + name + ".obj'");

  IdentityHeadReport rep;
  rep.modes = int(spec.weights.size());
  rep.vertices = int(n / 3);
  for (size_t i = 0; i < n; i += 3)
    rep.max_offset_cm = std::max(rep.max_offset_cm, std::hypot(neutral[i] - generic.v[i], neutral[i + 1] - generic.v[i + 1],
                                                               neutral[i + 2] - generic.v[i + 2]));
  fs::create_directories(out_dir);
  require(fs::absolute(out_dir) != fs::absolute(spec.ict_dir), "the output folder is the generic ICT folder");
  // Expressions first, the neutral last: a folder without its neutral is not
  // a head, so an interrupted write is never taken for one.
  std::vector<double> v(n);
  for (const auto& name : names) {
    const std::string p = spec.ict_dir + "/" + name + ".obj";
    ObjText e = read_obj_text(p);
    same_size(e, p);
    for (size_t i = 0; i < n; ++i) v[i] = neutral[i] + (e.v[i] - generic.v[i]);
    write_obj_text(out_dir + "/" + name + ".obj", e, v);
    ++rep.expressions;
  }
  fs::copy_file(meta_path, out_dir + "/vertex_indices.json", fs::copy_options::overwrite_existing);
  write_obj_text(out_dir + "/generic_neutral_mesh.obj", generic, neutral);
  return rep;
}

}  // namespace facesr
