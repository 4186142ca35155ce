// EvalReport's JSON and Markdown forms (declared in eval/evaluate.h).
#include <cstdio>
#include <sstream>

#include "eval/evaluate.h"

namespace facesr {
namespace {

nlohmann::json stats_json(const ErrorStats& s) {
  return {{"mean", s.mean}, {"median", s.median}, {"std", s.std}, {"max", s.max}, {"min", s.min}};
}

std::string fmt(const char* f, double v) {
  char buf[48];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// Method names go into a table cell: a '|' would split it.
std::string cell(const std::string& s) {
  std::string r;
  for (const char c : s) r += c == '|' ? std::string("\\|") : std::string(1, c);
  return r;
}

}  // namespace

nlohmann::json EvalReport::to_json() const {
  nlohmann::json j;
  j["units"] = "cm";
  j["test_frames"] = frames.size();
  if (frames_ours_beats_embedded >= 0) j["frames_ours_beats_embedded"] = frames_ours_beats_embedded;
  nlohmann::json order = nlohmann::json::array();
  for (const MethodReport& m : methods) {
    nlohmann::json o = {{"mean_cm", m.vertex_cm.mean},
                        {"median_cm", m.vertex_cm.median},
                        {"std_cm", m.vertex_cm.std},
                        {"max_cm", m.vertex_cm.max},
                        {"min_cm", m.vertex_cm.min},
                        {"dame", m.dame},
                        {"normal_deg", m.normal_deg},
                        {"normalized", stats_json(m.normalized)},
                        {"frame_mean_cm", stats_json(m.frame_cm)}};
    if (spectral) {
      o["low_band_fraction"] = m.bands.low_fraction;
      o["high_band_fraction"] = m.bands.high_fraction;
      o["low_band_rms_cm"] = m.bands.low_rms_cm;
      o["high_band_rms_cm"] = m.bands.high_rms_cm;
    }
    j[m.name] = o;
    order.push_back(m.name);
  }
  nlohmann::json e = {{"methods", order},
                      {"normalizer_cm", normalizer_cm},
                      {"dame_units", "rad"},
                      {"dame_masking_rad", dame.masking_rad},
                      {"normal_error", "mean angle between area-weighted vertex normals, degrees"},
                      {"csv", csv_path},
                      {"svg", svg_path},
                      {"pictures", pictures},
                      {"heat_scale_cm", heat_scale_cm}};
  if (spectral)
    e["spectral"] = {{"k", spectral_k},
                     {"eigenvalue_k_per_cm2", eigenvalue_k},
                     {"cutoff_wavelength_cm", cutoff_wavelength_cm},
                     {"basis_seconds", spectral_seconds},
                     {"solver", spectral_solver},
                     {"area_cm2", area_cm2}};
  j["eval"] = e;
  return j;
}

std::string EvalReport::to_markdown() const {
  std::ostringstream s;
  s << "| Method | Mean | Median | Std. | Max. | Min. | mean (cm) | median (cm) | std (cm) | max (cm) | DAME (rad) "
       "| normal (deg) |";
  if (spectral) s << " low band | high band |";
  s << "\n|---|---|---|---|---|---|---|---|---|---|---|---|";
  if (spectral) s << "---|---|";
  s << '\n';
  for (const MethodReport& m : methods) {
    s << "| " << cell(m.name) << " | " << fmt("%.2f", m.normalized.mean) << " | " << fmt("%.2f", m.normalized.median)
      << " | " << fmt("%.2f", m.normalized.std) << " | " << fmt("%.2f", m.normalized.max) << " | "
      << fmt("%.2f", m.normalized.min) << " | " << fmt("%.4f", m.vertex_cm.mean) << " | "
      << fmt("%.4f", m.vertex_cm.median) << " | " << fmt("%.4f", m.vertex_cm.std) << " | "
      << fmt("%.4f", m.vertex_cm.max) << " | " << fmt("%.5f", m.dame) << " | " << fmt("%.3f", m.normal_deg) << " |";
    if (spectral)
      s << ' ' << fmt("%.1f%%", 100 * m.bands.low_fraction) << " | " << fmt("%.1f%%", 100 * m.bands.high_fraction)
        << " |";
    s << '\n';
  }
  s << "\nMean to Min.: as in the paper's table 1, statistics over the " << frames.size()
    << " test frames of each method's frame-wise mean per-vertex error, divided by the largest frame-wise mean "
       "error of any method ("
    << fmt("%.4f", normalizer_cm)
    << " cm). The cm columns: per-vertex Euclidean error over all vertices of all test frames. DAME: dihedral "
       "angle mesh error (Váša and Rus 2012; area weighted, masking at "
    << fmt("%.2f", dame.masking_rad)
    << " rad, border edges skipped), mean over frames. Normal: mean angle between area-weighted vertex normals.";
  if (frames_ours_beats_embedded >= 0)
    s << " Ours has a lower frame mean error than embedded on " << frames_ours_beats_embedded << " of " << frames.size()
      << " frames.";
  if (spectral)
    s << " Low/high band: share of the error's squared area-weighted norm in the first " << spectral_k
      << " eigenvectors of the cotangent Laplacian with Voronoi mass (wavelengths above "
      << fmt("%.2f", cutoff_wavelength_cm) << " cm) and in the rest.";
  s << '\n';
  return s.str();
}

}  // namespace facesr
