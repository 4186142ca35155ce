#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/band_split.h"
#include "eval/dame.h"
#include "eval/error_stats.h"
#include "eval/frame_id.h"
#include "eval/spectral_basis.h"
#include "rig/rig.h"

// Evaluation of super-resolution methods against the HR simulation (paper
// §5.2: table 1, fig. 5, fig. 6), with the thesis's perceptual (DAME, normal)
// and spectral (low/high frequency) views of the same errors.
namespace facesr {

// One test frame: the HR simulation's surface displacement (M x 3 floats, cm,
// from rig.surface; a dataset frame's hr_disp).
struct EvalFrame {
  std::string sequence;  // performance name, e.g. "anger"
  int frame = 0;         // index within the sequence
  std::vector<float> reference_disp;
};

// One method: its predicted surface displacement (M x 3 floats, cm, from
// rig.surface) for every test frame, in the order of the test frames. Any
// name but the report's own top-level keys ("units", "test_frames",
// "frames_ours_beats_embedded", "eval"); "ours" and "embedded" are
// recognised for frames_ours_beats_embedded and "ours" is drawn in red.
struct EvalMethod {
  std::string name;
  std::vector<std::vector<float>> predicted_disp;
};

struct EvalOptions {
  bool spectral = true;              // compute the low/high band split
  SpectralOptions spectral_options;  // k of the split (when no basis is given)
  // A basis precomputed for this rig (spectral_basis(rig.surface,
  // rig.surface_tris, ...)): it is the same for every evaluation of the rig,
  // so callers evaluating several times should compute it once. Not owned.
  const SpectralBasis* basis = nullptr;
  DameOptions dame;
  // Outputs, each written (atomically) only when its path is non-empty. The
  // folders of csv_path and svg_path must exist; picture_dir is created. The
  // pictures are picture_dir/error_<sequence>_<frame>.png (sequence names
  // reduced to [A-Za-z0-9_-]), one panel for the HR reference and one per
  // method, all on one heat scale.
  std::string csv_path;  // frame-wise mean errors (write_frame_error_csv)
  std::string svg_path;  // fig. 5 plot (frame_error_svg)
  std::string title = "Frame-wise surface reconstruction error on the test frames";
  std::string picture_dir;          // fig. 6 heat maps, created when missing
  std::vector<int> picture_frames;  // indices into the test frames to picture
  double heat_scale_cm = 0;         // heat scale maximum; 0: the largest error over the pictured frames
  int tile_width = 360;             // pixels per picture panel
};

struct MethodReport {
  std::string name;
  ErrorStats vertex_cm;               // per-vertex error over all vertices of all test frames (cm)
  std::vector<double> frame_mean_cm;  // per test frame, mean per-vertex error (fig. 5)
  ErrorStats frame_cm;                // statistics of frame_mean_cm (cm)
  ErrorStats normalized;              // frame_cm / the common normaliser (table 1)
  double dame = 0;                    // mean over the test frames (radians)
  double normal_deg = 0;              // mean over the test frames of mean_normal_angle_deg
  BandSplit bands;                    // accumulated over the test frames (when spectral)
};

struct EvalReport {
  std::vector<FrameId> frames;
  std::vector<MethodReport> methods;    // in the order given
  double normalizer_cm = 0;             // largest frame mean error of any method (table 1)
  int frames_ours_beats_embedded = -1;  // -1 unless methods "ours" and "embedded" both exist
  DameOptions dame;
  bool spectral = false;
  int spectral_k = 0;
  double spectral_seconds = 0;  // time the basis took to compute (here or by the caller)
  double eigenvalue_k = 0;      // lambda_k, 1/cm^2
  double cutoff_wavelength_cm = 0;
  std::string spectral_solver;
  double area_cm2 = 0;
  std::string csv_path, svg_path;     // written files ("" when not)
  std::vector<std::string> pictures;  // written heat-map PNGs
  double heat_scale_cm = 0;           // scale used for them

  const MethodReport* method(const std::string& name) const;  // nullptr when absent

  // {"units": "cm", "test_frames": F, ["frames_ours_beats_embedded": n,]
  //  "<method>": {"mean_cm", "median_cm", "std_cm", "max_cm", "min_cm" (per
  //    vertex, all frames), "dame" (rad), "normal_deg",
  //    "normalized": {"mean", "median", "std", "max", "min"} (table 1),
  //    "frame_mean_cm": {same keys} (statistics of the fig. 5 curve, cm),
  //    ["low_band_fraction", "high_band_fraction", "low_band_rms_cm",
  //     "high_band_rms_cm"] (when spectral)},
  //  "eval": {"methods": [names in order], "normalizer_cm", "dame_units",
  //    "dame_masking_rad", "normal_error", ["spectral": {...}], "csv", "svg",
  //    "pictures", "heat_scale_cm"}}
  nlohmann::json to_json() const;
  // A Markdown table for BENCHMARKS.md: one row per method, the table 1
  // columns (normalised), then cm, DAME, normal error and the band split,
  // followed by a note saying what each column is.
  std::string to_markdown() const;
};

// Evaluates every method on every test frame. All input is checked before
// anything is computed or written: no frames or no methods, an empty,
// duplicate or reserved method name, a method with the wrong number of
// frames, a displacement of the wrong size or with a non-finite value, a
// picture frame out of range, a basis of another surface, or an output folder
// that does not exist are Errors naming the method and frame at fault.
EvalReport evaluate(const Rig& rig, const std::vector<EvalFrame>& frames, const std::vector<EvalMethod>& methods,
                    const EvalOptions& opt = {});

}  // namespace facesr
