#include "eval/evaluate.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>

#include "core/error.h"
#include "eval/dame.h"
#include "eval/frame_error_csv.h"
#include "eval/frame_error_svg.h"
#include "eval/interior_edges.h"
#include "eval/normal_error.h"
#include "eval/table1_normalization.h"
#include "eval/vertex_error.h"
#include "render/error_render.h"

namespace fs = std::filesystem;

namespace facesr {
namespace {

const std::set<std::string>& reserved_names() {
  static const std::set<std::string> r = {"units", "test_frames", "frames_ours_beats_embedded", "eval"};
  return r;
}

std::string frame_name(const std::vector<EvalFrame>& frames, size_t f) {
  return "test frame " + std::to_string(f) + " ('" + frames[f].sequence + "' #" + std::to_string(frames[f].frame) + ")";
}

long first_non_finite(const std::vector<float>& v) {
  for (size_t i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return long(i);
  return -1;
}

void check_disp(const std::vector<float>& d, size_t M, const std::string& who) {
  require(d.size() == 3 * M, who + ": " + std::to_string(d.size()) + " floats, expected " + std::to_string(3 * M) +
                                 " (" + std::to_string(M) + " surface vertices x 3)");
  if (const long k = first_non_finite(d); k >= 0)
    throw Error(who + ": vertex " + std::to_string(k / 3) + " has a non-finite displacement");
}

void check_output_folder(const std::string& path, const std::string& what) {
  if (path.empty()) return;
  const fs::path parent = fs::path(path).parent_path();
  require(parent.empty() || fs::is_directory(parent),
          "evaluate: the folder of the " + what + " '" + path + "' does not exist");
}

void validate(const Rig& rig, const std::vector<EvalFrame>& frames, const std::vector<EvalMethod>& methods,
              const EvalOptions& opt) {
  const size_t M = size_t(rig.num_surface_vertices());
  require(M > 0 && rig.surface_tris.rows() > 0, "evaluate: rig '" + rig.name + "' has an empty face surface");
  require(!frames.empty(), "evaluate: no test frames given");
  require(!methods.empty(), "evaluate: no methods given");
  for (size_t f = 0; f < frames.size(); ++f)
    check_disp(frames[f].reference_disp, M, "evaluate: " + frame_name(frames, f) + ", reference displacement");
  std::set<std::string> seen;
  for (const EvalMethod& m : methods) {
    require(!m.name.empty(), "evaluate: a method has an empty name");
    require(!reserved_names().count(m.name),
            "evaluate: method '" + m.name + "' has the name of a report key; pick another");
    require(seen.insert(m.name).second, "evaluate: method '" + m.name + "' is given twice");
    require(m.predicted_disp.size() == frames.size(),
            "evaluate: method '" + m.name + "' has " + std::to_string(m.predicted_disp.size()) +
                " predicted frames for " + std::to_string(frames.size()) + " test frames");
    for (size_t f = 0; f < frames.size(); ++f)
      check_disp(m.predicted_disp[f], M, "evaluate: method '" + m.name + "', " + frame_name(frames, f));
  }
  for (const int p : opt.picture_frames)
    require(p >= 0 && size_t(p) < frames.size(), "evaluate: picture frame " + std::to_string(p) + " is outside the " +
                                                     std::to_string(frames.size()) + " test frames");
  require(std::isfinite(opt.heat_scale_cm) && opt.heat_scale_cm >= 0,
          "evaluate: the heat scale must be a finite number of cm >= 0 (0: automatic)");
  require(opt.picture_frames.empty() || (opt.tile_width >= 64 && opt.tile_width <= 4096),
          "evaluate: tile width " + std::to_string(opt.tile_width) + " is outside [64, 4096]");
  if (opt.spectral && opt.basis)
    require(opt.basis->num_vertices() == long(M) && opt.basis->k > 0,
            "evaluate: the spectral basis has " + std::to_string(opt.basis->num_vertices()) + " vertices, but rig '" +
                rig.name + "' has " + std::to_string(M) + " surface vertices");
  check_output_folder(opt.csv_path, "frame error CSV");
  check_output_folder(opt.svg_path, "frame error plot");
  if (!opt.picture_dir.empty())
    require(!fs::exists(opt.picture_dir) || fs::is_directory(opt.picture_dir),
            "evaluate: picture folder '" + opt.picture_dir + "' exists and is not a folder");
}

Points positions(const Rig& rig, const std::vector<float>& disp) {
  Points P = rig.surface;
  for (long v = 0; v < P.rows(); ++v)
    for (int c = 0; c < 3; ++c) P(v, c) += double(disp[size_t(3 * v + c)]);
  return P;
}

Points difference(const std::vector<float>& a, const std::vector<float>& b) {
  Points D(long(a.size() / 3), 3);
  for (long v = 0; v < D.rows(); ++v)
    for (int c = 0; c < 3; ++c) D(v, c) = double(a[size_t(3 * v + c)]) - double(b[size_t(3 * v + c)]);
  return D;
}

std::vector<float> to_float(const Points& P) {
  std::vector<float> out(size_t(P.rows()) * 3);
  for (long v = 0; v < P.rows(); ++v)
    for (int c = 0; c < 3; ++c) out[size_t(3 * v + c)] = float(P(v, c));
  return out;
}

// File names from sequence names: keep them portable whatever the performance is called.
std::string file_safe(const std::string& s) {
  std::string r;
  for (const char c : s) r += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '_') ? c : '_';
  return r.empty() ? "seq" : r;
}

struct FrameResult {
  double mean = 0, dame = 0, normal = 0;
  BandSplit bands;
};

void write_pictures(const Rig& rig, const std::vector<EvalFrame>& frames, const std::vector<EvalMethod>& methods,
                    const std::vector<std::vector<std::vector<double>>>& errors, const EvalOptions& opt,
                    EvalReport& report) {
  double scale = opt.heat_scale_cm;
  if (scale == 0) {
    for (const auto& per_method : errors)
      for (const auto& e : per_method)
        for (const double x : e) scale = std::max(scale, x);
    // An exact method everywhere still needs a scale the renderer accepts.
    if (scale == 0) scale = 0.1;
  }
  report.heat_scale_cm = scale;
  fs::create_directories(opt.picture_dir);
  const size_t M = size_t(rig.num_surface_vertices());
  for (size_t p = 0; p < opt.picture_frames.size(); ++p) {
    const size_t f = size_t(opt.picture_frames[p]);
    std::vector<std::vector<float>> pos, err;
    std::vector<std::string> labels;
    // The HR reference first (error 0), as in fig. 6, then every method.
    pos.push_back(to_float(positions(rig, frames[f].reference_disp)));
    err.emplace_back(M, 0.0f);
    // The panel font has no '#'.
    labels.push_back("HR reference " + frames[f].sequence + " frame " + std::to_string(frames[f].frame));
    for (size_t m = 0; m < methods.size(); ++m) {
      pos.push_back(to_float(positions(rig, methods[m].predicted_disp[f])));
      err.emplace_back(errors[m][p].begin(), errors[m][p].end());
      char mean[48];
      std::snprintf(mean, sizeof mean, "  mean %.3f cm", report.methods[m].frame_mean_cm[f]);
      labels.push_back(methods[m].name + mean);
    }
    const std::string path = (fs::path(opt.picture_dir) / ("error_" + file_safe(frames[f].sequence) + "_" +
                                                           std::to_string(frames[f].frame) + ".png"))
                                 .string();
    render_error_png(rig, pos, err, labels, scale, path, opt.tile_width);
    report.pictures.push_back(path);
  }
}

}  // namespace

const MethodReport* EvalReport::method(const std::string& name) const {
  for (const MethodReport& m : methods)
    if (m.name == name) return &m;
  return nullptr;
}

EvalReport evaluate(const Rig& rig, const std::vector<EvalFrame>& frames, const std::vector<EvalMethod>& methods,
                    const EvalOptions& opt) {
  validate(rig, frames, methods, opt);
  const InteriorEdges edges = interior_edges(rig.surface_tris, rig.surface.rows());

  EvalReport report;
  report.dame = opt.dame;
  for (const EvalFrame& f : frames) report.frames.push_back({f.sequence, f.frame});

  SpectralBasis own;
  const SpectralBasis* basis = nullptr;
  if (opt.spectral) {
    if (opt.basis) {
      basis = opt.basis;
    } else {
      own = spectral_basis(rig.surface, rig.surface_tris, opt.spectral_options);
      basis = &own;
    }
    report.spectral = true;
    report.spectral_k = basis->k;
    report.spectral_seconds = basis->seconds;
    report.eigenvalue_k = basis->eigenvalues[basis->k - 1];
    report.cutoff_wavelength_cm = basis->cutoff_wavelength_cm();
    report.spectral_solver = basis->solver;
    report.area_cm2 = basis->area_cm2;
  }

  // The reference surfaces are shared by every method: build them once.
  const long F = long(frames.size());
  std::vector<Points> reference(static_cast<size_t>(F));
  for (long f = 0; f < F; ++f) reference[size_t(f)] = positions(rig, frames[size_t(f)].reference_disp);

  // errors[m][p]: per-vertex errors of method m on picture frame p (kept for the heat maps).
  std::vector<std::vector<std::vector<double>>> picture_errors(methods.size());
  for (size_t m = 0; m < methods.size(); ++m) {
    const EvalMethod& method = methods[m];
    MethodReport r;
    r.name = method.name;
    std::vector<FrameResult> res(static_cast<size_t>(F));
    std::vector<std::vector<double>> vertex(static_cast<size_t>(F));
    std::string failure;
    // Frames are independent; input was validated, so a throw here is a bug,
    // but it must still not escape the parallel region.
#pragma omp parallel for schedule(dynamic)
    for (long f = 0; f < F; ++f) {
      try {
        const auto& pred = method.predicted_disp[size_t(f)];
        const auto& ref = frames[size_t(f)].reference_disp;
        vertex[size_t(f)] = vertex_error(pred, ref, "evaluate");
        FrameResult& fr = res[size_t(f)];
        for (const double d : vertex[size_t(f)]) fr.mean += d;
        fr.mean /= double(vertex[size_t(f)].size());
        const Points test = positions(rig, pred);
        fr.dame = dame(reference[size_t(f)], test, edges, opt.dame);
        fr.normal = mean_normal_angle_deg(reference[size_t(f)], test, rig.surface_tris);
        if (basis) fr.bands = band_split(*basis, difference(pred, ref));
      } catch (const std::exception& e) {
#pragma omp critical
        failure = e.what();
      }
    }
    require(failure.empty(), "evaluate: method '" + method.name + "': " + failure);

    std::vector<double> all;
    all.reserve(size_t(F) * vertex[0].size());
    std::vector<BandSplit> bands;
    for (long f = 0; f < F; ++f) {
      all.insert(all.end(), vertex[size_t(f)].begin(), vertex[size_t(f)].end());
      r.frame_mean_cm.push_back(res[size_t(f)].mean);
      r.dame += res[size_t(f)].dame / double(F);
      r.normal_deg += res[size_t(f)].normal / double(F);
      bands.push_back(res[size_t(f)].bands);
    }
    for (const int p : opt.picture_frames) picture_errors[m].push_back(vertex[size_t(p)]);
    vertex.clear();
    r.vertex_cm = error_stats(std::move(all));
    r.frame_cm = error_stats(r.frame_mean_cm);
    if (basis) r.bands = accumulate(bands, basis->area_cm2);
    report.methods.push_back(std::move(r));
  }

  std::vector<std::vector<double>> frame_means;
  std::vector<std::string> names;
  for (const MethodReport& r : report.methods) {
    frame_means.push_back(r.frame_mean_cm);
    names.push_back(r.name);
  }
  report.normalizer_cm = table1_normalizer(frame_means);
  const std::vector<ErrorStats> norm = table1_normalized_stats(frame_means);
  for (size_t m = 0; m < report.methods.size(); ++m) report.methods[m].normalized = norm[m];

  const MethodReport *ours = report.method("ours"), *embedded = report.method("embedded");
  if (ours && embedded) {
    report.frames_ours_beats_embedded = 0;
    for (long f = 0; f < F; ++f)
      if (ours->frame_mean_cm[size_t(f)] < embedded->frame_mean_cm[size_t(f)]) ++report.frames_ours_beats_embedded;
  }

  // Everything is computed; only now touch the disk.
  if (!opt.csv_path.empty()) {
    write_frame_error_csv(opt.csv_path, report.frames, names, frame_means);
    report.csv_path = opt.csv_path;
  }
  if (!opt.svg_path.empty()) {
    write_frame_error_svg(opt.svg_path, report.frames, names, frame_means, opt.title);
    report.svg_path = opt.svg_path;
  }
  if (!opt.picture_dir.empty() && !opt.picture_frames.empty())
    write_pictures(rig, frames, methods, picture_errors, opt, report);
  return report;
}

}  // namespace facesr
