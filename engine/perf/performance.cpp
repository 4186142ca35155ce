#include "perf/performance.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/number_text.h"
#include "perf/perf_limits.h"

namespace facesr {
namespace {

constexpr const char* kFormat = "facesr-performance";
constexpr int kVersion = 1;
using namespace perf_limits;
// Bounds on an explicit jaw transform: beyond any real jaw (about 30-35
// degrees of opening, a few mm of protrusion), so they only catch radians
// passed as degrees or millimetres as centimetres.
constexpr double kMaxJawDeg = 60;
constexpr double kMaxJawCm = 5;

// As the messages have always named values: "NaN", 6 digits.
std::string control_text(double v) { return std::isnan(v) ? "NaN" : number_text(v, 6); }

// "unknown blendshape 'jawopen' (did you mean 'jawOpen'?)" or a few valid names.
std::string unknown_name_message(const std::string& name, const std::vector<std::string>& rig_names) {
  std::string msg = "unknown blendshape '" + name + "'";
  for (const auto& n : rig_names)
    if (lower(n) == lower(name)) return msg + " (did you mean '" + n + "'?)";
  if (rig_names.empty()) return msg + " (the rig has no blendshapes)";
  msg += " (the rig has " + std::to_string(rig_names.size()) + ", e.g. ";
  const size_t shown = std::min<size_t>(rig_names.size(), 6);
  for (size_t i = 0; i < shown; ++i) msg += (i ? ", " : "") + rig_names[i];
  return msg + (shown < rig_names.size() ? ", ...)" : ")");
}

double number_field(const nlohmann::json& j, const char* key, const std::string& where) {
  require(j.contains(key), where + ": '" + key + "' is missing");
  require(j[key].is_number(), where + ": '" + key + "' is not a number (got " + j[key].dump() + ")");
  return j[key].get<double>();
}

struct Keyframe {
  double time = 0;
  std::vector<float> w;    // rig order; unlisted shapes are 0
  std::vector<float> jaw;  // empty, or rotation (degrees) and translation (cm)
};

// One "jaw" member: [x, y, z], finite; a missing member is zero.
void parse_jaw_vector(const nlohmann::json& jaw, const char* key, const std::string& where, double bound,
                      const char* unit, float* out) {
  if (!jaw.contains(key)) return;
  const auto& a = jaw[key];
  const std::string what = where + ": jaw '" + key + "'";
  require(a.is_array() && a.size() == 3, what + " is not an array of 3 numbers (got " + a.dump() + ")");
  double norm2 = 0;
  for (int i = 0; i < 3; ++i) {
    require(a[i].is_number(), what + "[" + std::to_string(i) + "] is not a number (got " + a[i].dump() + ")");
    const double v = a[i].get<double>();
    require(std::isfinite(v), what + "[" + std::to_string(i) + "] is " + control_text(v) + " (must be finite)");
    out[i] = float(v);
    norm2 += v * v;
  }
  require(std::sqrt(norm2) <= bound, what + " has length " + control_text(std::sqrt(norm2)) + " " + unit +
                                         ", more than " + control_text(bound) + " " + unit);
}

std::vector<float> parse_jaw(const nlohmann::json& jaw, const std::string& where) {
  require(jaw.is_object(),
          where + ": 'jaw' is not an object {\"rotation_deg\": [x, y, z], \"translation_cm\": [x, y, z]}");
  for (const auto& [key, value] : jaw.items())
    require(key == "rotation_deg" || key == "translation_cm",
            where + ": 'jaw' has unknown member '" + key + "' (expected rotation_deg, translation_cm)");
  std::vector<float> out(6, 0.0f);
  parse_jaw_vector(jaw, "rotation_deg", where, kMaxJawDeg, "degrees", out.data());
  parse_jaw_vector(jaw, "translation_cm", where, kMaxJawCm, "cm", out.data() + 3);
  return out;
}

Keyframe parse_keyframe(const nlohmann::json& k, size_t index, const std::map<std::string, size_t>& slot,
                        const std::vector<std::string>& rig_names, const std::string& context) {
  const std::string where = context + ": keyframe " + std::to_string(index);
  require(k.is_object(), where + ": is not an object");
  Keyframe key;
  key.time = number_field(k, "time", where);
  require(std::isfinite(key.time), where + ": time is " + control_text(key.time) + " (must be finite)");
  require(k.contains("weights") && k["weights"].is_object(),
          where + ": 'weights' is missing or not an object of name: weight");
  key.w.assign(rig_names.size(), 0.0f);
  for (const auto& [name, value] : k["weights"].items()) {
    const auto it = slot.find(name);
    require(it != slot.end(), where + ": " + unknown_name_message(name, rig_names));
    const std::string wname = where + ": weight '" + name + "'";
    require(value.is_number(), wname + " is not a number (got " + value.dump() + ")");
    const double v = value.get<double>();
    require(!std::isnan(v), wname + " is NaN");
    require(std::isfinite(v), wname + " is infinite");
    require(v >= 0 && v <= 1, wname + " is " + control_text(v) + ", outside [0, 1]");
    key.w[it->second] = float(v);
  }
  if (k.contains("jaw")) key.jaw = parse_jaw(k["jaw"], where);
  return key;
}

void lerp(const std::vector<float>& a, const std::vector<float>& b, double alpha, float* out) {
  for (size_t i = 0; i < a.size(); ++i) out[i] = float(a[i] + alpha * (double(b[i]) - a[i]));
}

// Weights (and jaw, when `jaw_out` is given) at time t by linear
// interpolation; `k` is the keyframe at or before t.
void sample(const std::vector<Keyframe>& keys, size_t k, double t, float* out, float* jaw_out) {
  auto copy = [&](const Keyframe& key) {
    std::copy(key.w.begin(), key.w.end(), out);
    if (jaw_out) std::copy(key.jaw.begin(), key.jaw.end(), jaw_out);
  };
  if (k + 1 >= keys.size()) return copy(keys[k]);
  double alpha = (t - keys[k].time) / (keys[k + 1].time - keys[k].time);
  // Snap times that hit a keyframe up to rounding, so a saved performance
  // reloads bit for bit and zero weights stay exactly zero.
  if (alpha <= 1e-9) return copy(keys[k]);
  if (alpha >= 1 - 1e-9) return copy(keys[k + 1]);
  lerp(keys[k].w, keys[k + 1].w, alpha, out);
  if (jaw_out) lerp(keys[k].jaw, keys[k + 1].jaw, alpha, jaw_out);
}

// Shortest decimal that reads back as the same float, so files say 0.3, not
// 0.30000001192092896, and still reload exactly.
double shortest_float(float v) {
  char buf[32];
  for (int digits = 1; digits <= 9; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, double(v));
    if (std::strtof(buf, nullptr) == v) return std::strtod(buf, nullptr);
  }
  return double(v);
}

}  // namespace

Performance performance_from_json(const nlohmann::json& j, const std::vector<std::string>& rig_names,
                                  const std::string& context) {
  require(j.is_object(), context + ": is not a JSON object");
  require(j.contains("format") && j["format"].is_string() && j["format"].get<std::string>() == kFormat,
          context + ": 'format' is " + (j.contains("format") ? j["format"].dump() : std::string("missing")) +
              ", expected \"" + kFormat + "\"");
  require(j.contains("version"), context + ": 'version' is missing (expected " + std::to_string(kVersion) + ")");
  require(j["version"].is_number() && j["version"].get<double>() == kVersion,
          context + ": unsupported version " + j["version"].dump() + " (expected " + std::to_string(kVersion) + ")");

  Performance perf;
  perf.names = rig_names;
  if (j.contains("name")) {
    require(j["name"].is_string(), context + ": 'name' is not a string");
    perf.name = j["name"].get<std::string>();
  }
  perf.fps = number_field(j, "fps", context);
  require(perf.fps > 0 && perf.fps <= kMaxFps, context + ": fps " + control_text(perf.fps) + " is not in (0, 1000]");

  require(j.contains("keyframes") && j["keyframes"].is_array(), context + ": 'keyframes' is missing or not an array");
  const auto& jk = j["keyframes"];
  require(!jk.empty(), context + ": 'keyframes' is empty (need at least 1 keyframe)");
  std::map<std::string, size_t> slot;
  for (size_t i = 0; i < rig_names.size(); ++i) slot.emplace(rig_names[i], i);
  std::vector<Keyframe> keys;
  keys.reserve(jk.size());
  for (size_t i = 0; i < jk.size(); ++i) {
    keys.push_back(parse_keyframe(jk[i], i, slot, rig_names, context));
    if (i > 0 && !(keys[i].time > keys[i - 1].time))
      throw Error(context + ": keyframe " + std::to_string(i) + ": time " + control_text(keys[i].time) +
                  " is not after keyframe " + std::to_string(i - 1) + "'s time " + control_text(keys[i - 1].time) +
                  " (times must be strictly increasing)");
    if (i > 0 && keys[i].jaw.empty() != keys[0].jaw.empty())
      throw Error(context + ": keyframe " + std::to_string(i) + (keys[i].jaw.empty() ? " has no" : " has a") +
                  " 'jaw' but keyframe 0 " + (keys[0].jaw.empty() ? "has none" : "has one") +
                  " (either every keyframe has 'jaw' or none does)");
  }
  perf.has_jaw = !keys[0].jaw.empty();

  perf.start_time = keys.front().time;
  const double span = (keys.back().time - keys.front().time) * perf.fps;
  require(span < kMaxFrames, context + ": keyframes span " + control_text(keys.back().time - keys.front().time) +
                                 " s, more than " + control_text(kMaxFrames) + " frames at " + control_text(perf.fps) +
                                 " fps");
  const int frames = int(std::floor(span + 1e-6)) + 1;
  perf.weights.assign(size_t(frames) * rig_names.size(), 0.0f);
  if (perf.has_jaw) perf.jaw.assign(size_t(frames) * 6, 0.0f);
  size_t k = 0;
  for (int f = 0; f < frames; ++f) {
    const double t = std::min(perf.time(f), keys.back().time);
    while (k + 1 < keys.size() && keys[k + 1].time <= t) ++k;
    sample(keys, k, t, perf.weights.data() + size_t(f) * rig_names.size(),
           perf.has_jaw ? perf.jaw.data() + size_t(f) * 6 : nullptr);
  }
  return perf;
}

Performance load_performance_json(const std::string& path, const std::vector<std::string>& rig_blendshape_names) {
  std::ifstream in(path);
  require(in.good(), path + ": cannot open performance file (no such file or not readable)");
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(ss.str());
  } catch (const nlohmann::json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw Error(path + ": not valid JSON: " + e.what());
  }
  return performance_from_json(j, rig_blendshape_names, path);
}

nlohmann::json performance_to_json(const Performance& perf) {
  require(perf.fps > 0 && perf.fps <= kMaxFps,
          "performance '" + perf.name + "': fps " + control_text(perf.fps) + " is not in (0, 1000]");
  require(!perf.names.empty() && perf.weights.size() % perf.names.size() == 0 && perf.frames() > 0,
          "performance '" + perf.name + "': has " + std::to_string(perf.weights.size()) + " weights for " +
              std::to_string(perf.names.size()) + " shapes (need a whole number of frames, at least 1)");
  require(!perf.has_jaw || perf.jaw.size() == size_t(perf.frames()) * 6,
          "performance '" + perf.name + "': has " + std::to_string(perf.jaw.size()) + " jaw values for " +
              std::to_string(perf.frames()) + " frames (need 6 per frame)");
  nlohmann::json keyframes = nlohmann::json::array();
  for (int f = 0; f < perf.frames(); ++f) {
    nlohmann::json w = nlohmann::json::object();
    const float* row = perf.frame(f);
    for (size_t i = 0; i < perf.names.size(); ++i) w[perf.names[i]] = shortest_float(row[i]);
    nlohmann::json key = {{"time", perf.time(f)}, {"weights", std::move(w)}};
    if (perf.has_jaw) {
      const float* j = perf.jaw_frame(f);
      key["jaw"] = {{"rotation_deg", {shortest_float(j[0]), shortest_float(j[1]), shortest_float(j[2])}},
                    {"translation_cm", {shortest_float(j[3]), shortest_float(j[4]), shortest_float(j[5])}}};
    }
    keyframes.push_back(std::move(key));
  }
  return {{"format", kFormat},
          {"version", kVersion},
          {"name", perf.name},
          {"fps", perf.fps},
          {"keyframes", std::move(keyframes)}};
}

void save_performance_json(const Performance& perf, const std::string& path) {
  // One keyframe per line: readable, diffable, and still plain JSON.
  const nlohmann::json j = performance_to_json(perf);
  std::string text = "{\n";
  for (const char* key : {"format", "version", "name", "fps"})
    text += " \"" + std::string(key) + "\": " + j[key].dump() + ",\n";
  text += " \"keyframes\": [\n";
  const auto& keys = j["keyframes"];
  for (size_t i = 0; i < keys.size(); ++i) text += "  " + keys[i].dump() + (i + 1 < keys.size() ? ",\n" : "\n");
  text += " ]\n}\n";
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

std::vector<float> max_weights(const Performance& perf) {
  std::vector<float> m(perf.names.size(), 0.0f);
  for (int f = 0; f < perf.frames(); ++f)
    for (size_t i = 0; i < m.size(); ++i) m[i] = std::max(m[i], perf.frame(f)[i]);
  return m;
}

}  // namespace facesr
