#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

// A performance: ARKit blendshape weights over time, sampled at a fixed frame
// rate in the rig's blendshape order. It drives the simulators (through the
// rig's activation table and jaw shapes) and the paired-dataset generator.
//
// Keyframe JSON format, version 1:
//
//   {"format": "facesr-performance", "version": 1, "name": "smile", "fps": 30,
//    "keyframes": [{"time": 0.0, "weights": {"mouthSmile_L": 0.0, ...}},
//                  {"time": 1.0, "weights": {"mouthSmile_L": 1.0, ...}}, ...]}
//
//   format     required, "facesr-performance"
//   version    required, 1
//   name       optional string (default: empty)
//   fps        required, in (0, 1000]
//   keyframes  required, at least one; "time" in seconds, finite and strictly
//              increasing; "weights" maps rig blendshape names to [0, 1].
//   jaw        optional per keyframe: an explicit rigid jaw transform,
//                "jaw": {"rotation_deg": [rx, ry, rz], "translation_cm": [tx, ty, tz]}
//              a rotation vector (axis × angle in degrees, |r| <= 60) about
//              the rig's jaw pivot, then a translation (|t| <= 5 cm), both in
//              the rig's rest frame; a missing member is zero. Either every
//              keyframe has "jaw" or none does. Added within version 1: files
//              without it are unchanged and mean "the jaw follows the jaw
//              blendshapes".
//
// Sampling: frame f lies at t = t_first + f / fps, for every such t up to the
// last keyframe's time inclusive (a last keyframe off the frame grid is not
// sampled itself). Weights are linearly interpolated between the two
// keyframes around t. A blendshape not listed in a keyframe is 0 at that
// keyframe (it does not hold its previous value), so keyframes can list only
// the shapes they move; shapes never listed are 0 throughout. The jaw's six
// numbers are interpolated component-wise the same way (for rotation vectors
// this is exact about a fixed axis and close enough between nearby keyframes).
namespace facesr {

struct LiveLinkReport;   // perf/livelink_csv.h
struct LiveLinkOptions;  // perf/livelink_csv.h

struct Performance {
  std::string name;
  double fps = 30;
  double start_time = 0;           // seconds, time of frame 0 (the first keyframe's time)
  std::vector<std::string> names;  // the rig's blendshape order
  std::vector<float> weights;      // frames × names.size(), row-major
  // Optional explicit jaw: frames × 6, a rotation vector (degrees, axis·angle,
  // about the rig's jaw pivot) then a translation (cm), rig rest frame.
  // frame_controls (perf/perf_controls.h) turns it into Controls.
  bool has_jaw = false;
  std::vector<float> jaw;

  int frames() const {
    return names.empty() ? 0 : int(weights.size() / names.size());
  }
  const float* frame(int f) const { return weights.data() + size_t(f) * names.size(); }
  const float* jaw_frame(int f) const { return jaw.data() + size_t(f) * 6; }  // only when has_jaw
  double time(int f) const { return start_time + f / fps; }
  double duration() const { return frames() > 0 ? (frames() - 1) / fps : 0.0; }
};

// Parses and validates a keyframe JSON object; `context` (usually the file
// path) starts every Error message, e.g.
// "smile.json: keyframe 3: weight 'jawOpen' is 1.5, outside [0, 1]".
Performance performance_from_json(const nlohmann::json& j, const std::vector<std::string>& rig_names,
                                  const std::string& context);

// Reads and validates a keyframe JSON file against the rig's blendshape names.
Performance load_performance_json(const std::string& path,
                                  const std::vector<std::string>& rig_blendshape_names);

// The keyframe JSON of a performance: one keyframe per frame listing every
// shape. Weights are written as the exact float values, so loading the file
// again reproduces the weights bit for bit.
nlohmann::json performance_to_json(const Performance& perf);

// Writes performance_to_json atomically (no partial file on failure).
void save_performance_json(const Performance& perf, const std::string& path);

// Loads a performance by extension: ".json" keyframes (load_performance_json)
// or ".csv" Live Link Face capture (load_livelink_csv with `csv` options, by
// default lenient at 60 fps capture, 30 fps output; `csv_report`, if given,
// receives its column report and the warnings about what it repaired, which
// the caller should print). Any other extension is an Error naming the file.
Performance load_performance(const std::string& path, const std::vector<std::string>& rig_names,
                             LiveLinkReport* csv_report = nullptr);
Performance load_performance(const std::string& path, const std::vector<std::string>& rig_names,
                             const LiveLinkOptions& csv, LiveLinkReport* csv_report = nullptr);
// load_performance, then each repair's warning of a Live Link CSV printed on
// stderr as "[tag] path: warning: ..." whatever the caller's verbosity: a
// repaired capture is not quite the motion the file claims.
Performance load_performance_warned(const std::string& path, const std::vector<std::string>& rig_names,
                                    const LiveLinkOptions& csv, const std::string& tag,
                                    LiveLinkReport* csv_report = nullptr);

// Built-in performances at 30 fps: "smile", "jaw", "talk", "random",
// "sparse" and its other takes "sparse-2" ... "sparse-99" (see
// builtin_performance.cpp; the takes are not listed by
// builtin_performance_names) and the FACS-based emotions "amazement", "anger",
// "fear", "pain" (themed_performance.cpp, docs/performances.md). Shapes the
// rig lacks are skipped; an unknown name is an Error listing the valid ones.
Performance builtin_performance(const std::string& name, const std::vector<std::string>& rig_names);
std::vector<std::string> builtin_performance_names();

// Largest weight of each shape over all frames (same order as perf.names).
std::vector<float> max_weights(const Performance& perf);

}  // namespace facesr
