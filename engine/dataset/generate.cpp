#include "dataset/generate.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <cstring>
#include <fstream>
#include <memory>

#include "collide/mouth_collider.h"
#include "core/atomic_file.h"
#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "core/progress.h"
#include "dataset/dataset_io.h"
#include "dataset/dataset_manifest.h"
#include "dataset/dataset_metrics.h"
#include "perf/livelink_csv.h"
#include "perf/perf_controls.h"
#include "perf/performance.h"
#include "rig/rig_io.h"
#include "sim/cl_simulator.h"

namespace facesr {
namespace fs = std::filesystem;

nlohmann::json DatasetSummary::to_json() const {
  return {{"frames", frames},
          {"sequences", sequences},
          {"resumed_frames", resumed_frames},
          {"skipped_sequences", skipped_sequences},
          {"hr_mean_step_s", hr_mean_step_s},
          {"lr_mean_step_ms", lr_mean_step_ms},
          {"hr_over_lr_time", hr_over_lr_time},
          {"embedded_error_mean_cm", embedded_error_mean_cm},
          {"embedded_error_max_cm", embedded_error_max_cm},
          {"max_penetration_cm", max_penetration_cm},
          {"nan_frames", nan_frames},
          {"diverged_frames", diverged_frames},
          {"hr_capped_frames", hr_capped_frames},
          {"wall_s", wall_s},
          {"lr_device", lr_device},
          {"hr_device", hr_device},
          {"units", "cm"}};
}

namespace {

// Simulator state after the last written frame, so that an interrupted
// sequence resumes from where it stopped rather than from the rest pose.
// Layout: "FSRSTATE", u64 frame, LR nodes (f64 vector), HR nodes (f64 vector),
// u64 FNV-1a of everything before it.
void save_state(const std::string& path, uint64_t frame, const std::vector<double>& lr,
                const std::vector<double>& hr) {
  ByteWriter w;
  for (char c : std::string("FSRSTATE")) w.put(c);
  w.put(frame);
  w.put_vector(lr);
  w.put_vector(hr);
  w.put(fnv1a64(w.bytes().data(), w.bytes().size()));
  write_file_atomically(path, [&](std::ostream& o) {
    o.write(reinterpret_cast<const char*>(w.bytes().data()), std::streamsize(w.bytes().size()));
  });
}

// False when the file is missing, damaged or for another frame or mesh size.
bool load_state(const std::string& path, uint64_t frame, std::vector<double>& lr, std::vector<double>& hr) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (bytes.size() < 24 || std::string(bytes.begin(), bytes.begin() + 8) != "FSRSTATE") return false;
  uint64_t sum;
  std::memcpy(&sum, bytes.data() + bytes.size() - 8, 8);
  if (sum != fnv1a64(bytes.data(), bytes.size() - 8)) return false;
  try {
    ByteReader r(bytes.data() + 8, bytes.size() - 16, path);
    const auto f = r.get<uint64_t>("frame");
    auto l = r.get_vector<double>("LR nodes");
    auto h = r.get_vector<double>("HR nodes");
    if (f != frame || l.size() != lr.size() || h.size() != hr.size()) return false;
    lr.swap(l);
    hr.swap(h);
    return true;
  } catch (const Error&) {
    return false;
  }
}

std::vector<float> minus(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<float> d(a.size());
  for (size_t i = 0; i < a.size(); ++i) d[i] = float(a[i] - b[i]);
  return d;
}

struct Totals {
  double hr_s = 0, lr_ms = 0, err_sum = 0, err_max = 0, pen_max = 0;
  long vertex_frames = 0;
  int frames = 0, hr_capped = 0;
  // hr_tol: the HR Newton tolerance; frames that stopped above it are counted.
  void add(const DatasetFrame& f, double hr_tol) {
    hr_capped += f.stats.hr_rel_residual > hr_tol;
    double mean, max;
    embedded_error(f, mean, max);
    const long S = long(f.hr_disp.size() / 3);
    err_sum += mean * double(S);
    vertex_frames += S;
    err_max = std::max(err_max, max);
    hr_s += f.stats.hr_step_s;
    lr_ms += f.stats.lr_step_ms;
    pen_max = std::max(pen_max, double(f.stats.max_penetration_cm));
    ++frames;
  }
};

}  // namespace

DatasetSummary generate_dataset(const Rig& rig, const std::string& rig_path, const std::string& out_dir,
                                const DatasetOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  require(!opt.builtins.empty() || !opt.files.empty(), "dataset: no performances given");
  require(fs::is_directory(out_dir) || fs::create_directories(out_dir),
          "dataset: cannot create output folder '" + out_dir + "'");
  std::vector<Performance> perfs;
  for (const auto& b : opt.builtins) perfs.push_back(builtin_performance(b, rig.blendshape_names));
  for (const auto& f : opt.files) {
    perfs.push_back(load_performance_warned(f, rig.blendshape_names, opt.csv, "dataset"));
    if (perfs.back().name.empty()) perfs.back().name = fs::path(f).stem().string();
  }
  for (size_t i = 0; i < perfs.size(); ++i) {
    require(!perfs[i].name.empty(), "dataset: performance " + std::to_string(i) + " has no name");
    for (size_t j = 0; j < i; ++j)
      require(perfs[i].name != perfs[j].name, "dataset: two performances are named '" + perfs[i].name + "'");
    if (opt.max_frames > 0 && perfs[i].frames() > opt.max_frames)
      perfs[i].weights.resize(size_t(opt.max_frames) * perfs[i].names.size());
    if (opt.max_frames > 0 && perfs[i].has_jaw && perfs[i].jaw.size() > size_t(opt.max_frames) * 6)
      perfs[i].jaw.resize(size_t(opt.max_frames) * 6);
    require(perfs[i].frames() > 0, "dataset: performance '" + perfs[i].name + "' has no frames");
  }

  const SimModel lr_model = make_sim_model(rig, Resolution::Low);
  const SimModel hr_model = make_sim_model(rig, Resolution::High);
  std::unique_ptr<Simulator> lr;
  if (opt.lr_cpu) {
    lr = make_cpu_simulator(lr_model, opt.lr_solver);
  } else {
    ClSimulatorOptions cl;
    cl.device = compute::DeviceSelector::parse(opt.device);
    lr = make_cl_simulator(lr_model, opt.lr_solver, cl);
  }
  auto collider = std::make_shared<MouthCollider>(rig, hr_model);
  auto hr = make_cpu_simulator(hr_model, opt.hr_solver, collider, opt.collisions);

  const uint64_t checksum = rig_checksum(rig);
  const std::string manifest_path = out_dir + "/manifest.json";
  DatasetManifest manifest;
  if (!opt.restart && fs::exists(manifest_path)) {
    manifest = load_manifest(manifest_path);
    require(manifest.rig_checksum == checksum, manifest_path + ": made from another rig (checksum " +
                                                   std::to_string(manifest.rig_checksum) + ", this rig " +
                                                   std::to_string(checksum) + "); use --restart to replace it");
  }
  manifest.rig_name = rig.name;
  manifest.rig_checksum = checksum;
  manifest.rig_path = rig_path;
  manifest.fps = perfs[0].fps;
  manifest.num_lr_nodes = lr_model.num_nodes;
  manifest.num_surface = hr_model.num_surface;
  manifest.weight_names = rig.blendshape_names;
  manifest.extra["collisions"] = opt.collisions;
  // What "stopped above the tolerance" means for this dataset's HR frames.
  manifest.extra["hr_newton_tol"] = opt.hr_solver.newton_tol;
  manifest.extra["lr_device"] = lr->device();
  manifest.extra["hr_device"] = hr->device();
  manifest.extra["collision_region_nodes"] = collider->info().region_nodes;

  long total = 0;
  for (const auto& p : perfs) total += p.frames();
  Progress progress("dataset", total, opt.progress);
  DatasetSummary sum;
  sum.lr_device = lr->device();
  sum.hr_device = hr->device();
  Totals all;
  long done = 0;
  std::vector<double> xl, xh, sl, sh;
  for (const auto& perf : perfs) {
    const std::string file = perf.name + ".fsd";
    const std::string path = out_dir + "/" + file;
    const std::string state_path = out_dir + "/." + perf.name + ".state";
    DatasetHeader h;
    h.name = perf.name;
    h.rig_checksum = checksum;
    h.fps = perf.fps;
    h.num_lr_nodes = uint64_t(lr_model.num_nodes);
    h.num_surface = uint64_t(hr_model.num_surface);
    h.weight_names = rig.blendshape_names;
    const bool is_test = std::find(opt.test_names.begin(), opt.test_names.end(), perf.name) != opt.test_names.end();
    DatasetManifest::Entry entry;
    entry.name = perf.name;
    entry.file = file;
    entry.split = is_test ? "test" : "train";
    Totals seq;
    bool finished = false;
    if (!opt.restart && fs::exists(path)) {
      const DatasetHeader old = read_dataset_header(path);
      if (old.rig_checksum == checksum && old.num_frames == uint64_t(perf.frames()) &&
          old.num_lr_nodes == h.num_lr_nodes && old.num_surface == h.num_surface) {
        const DatasetSequence s = read_dataset_sequence(path);
        for (const auto& f : s.frames) seq.add(f, opt.hr_solver.newton_tol);
        finished = true;
        ++sum.skipped_sequences;
        done += perf.frames();
        progress.skip(perf.frames());
        progress.update(done, perf.name + ": already complete");
      }
    }
    if (!finished) {
      auto writer = std::make_unique<DatasetWriter>(path, h, opt.restart);
      uint64_t start = writer->frames();
      lr->reset();
      hr->reset();
      if (start > 0) {
        xl = lr_model.rest;
        xh = hr_model.rest;
        if (load_state(state_path, start - 1, xl, xh)) {
          lr->set_nodes(xl);
          hr->set_nodes(xh);
          sum.resumed_frames += int(start);
          if (opt.progress)
            std::fprintf(stderr, "[dataset] %s: resuming after frame %llu\n", perf.name.c_str(),
                         static_cast<unsigned long long>(start - 1));
        } else {
          if (opt.progress)
            std::fprintf(stderr, "[dataset] %s: no matching simulator state; starting the sequence over\n",
                         perf.name.c_str());
          writer.reset();
          writer = std::make_unique<DatasetWriter>(path, h, true);
          start = 0;
        }
      }
      done += long(start);
      progress.skip(long(start));
      Controls c;
      for (int f = int(start); f < perf.frames(); ++f) {
        frame_controls(perf, f, rig.jaw, c);
        const StepStats ls = lr->step(c);
        const StepStats hs = hr->step(c);
        lr->nodes(xl);
        lr->surface(sl);
        hr->nodes(xh);
        hr->surface(sh);
        bool finite = std::isfinite(ls.rel_residual) && std::isfinite(hs.rel_residual);
        for (double v : xh) finite = finite && std::isfinite(v);
        for (double v : xl) finite = finite && std::isfinite(v);
        if (!finite) {
          ++sum.nan_frames;
          throw Error("dataset: " + perf.name + " frame " + std::to_string(f) +
                      ": non-finite simulation result; the sequence stops at its last good frame");
        }
        if (ls.status == StepStatus::Diverged || hs.status == StepStatus::Diverged) {
          ++sum.diverged_frames;
          if (opt.progress)
            std::fprintf(stderr, "[dataset] %s frame %d: %s solve diverged past recovery; held at the last good state\n",
                         perf.name.c_str(), f, hs.status == StepStatus::Diverged ? "HR" : "LR");
        }
        DatasetFrame fr;
        fr.time = perf.time(f);
        fr.weights = c.weights;
        const FrameInputs in = prepare_frame(hr_model, c);
        for (int i = 0; i < 3; ++i) {
          for (int j = 0; j < 3; ++j) fr.jaw[3 * i + j] = float(in.jaw_R(i, j));
          fr.jaw[9 + i] = float(in.jaw_t[i]);
        }
        fr.lr_disp = minus(xl, lr_model.rest);
        fr.hr_disp = minus(sh, hr_model.surf_rest);
        fr.embedded_disp = minus(sl, lr_model.surf_rest);
        fr.stats.hr_step_s = hs.ms / 1e3;
        fr.stats.lr_step_ms = ls.ms;
        fr.stats.max_penetration_cm = float(hs.max_penetration_cm);
        fr.stats.contacts = hs.contacts;
        fr.stats.hr_newton_iters = hs.newton_iters;
        fr.stats.hr_cg_iters = hs.cg_iters;
        fr.stats.lr_newton_iters = ls.newton_iters;
        fr.stats.lr_cg_iters = ls.cg_iters;
        fr.stats.hr_rel_residual = float(hs.rel_residual);
        fr.stats.lr_rel_residual = float(ls.rel_residual);
        writer->add_frame(fr);
        save_state(state_path, uint64_t(f), xl, xh);
        seq.add(fr, opt.hr_solver.newton_tol);
        char detail[200];
        std::snprintf(detail, sizeof detail, "%s %d/%d: HR %.1f s (%d Newton, %d contacts, pen %.3f cm), LR %.0f ms",
                      perf.name.c_str(), f + 1, perf.frames(), hs.ms / 1e3, hs.newton_iters, hs.contacts,
                      hs.max_penetration_cm, ls.ms);
        progress.update(++done, detail);
      }
      writer->commit();
      fs::remove(state_path);
      // Frames recovered from an interrupted run count in the totals too.
      if (start > 0) {
        const DatasetSequence s = read_dataset_sequence(path);
        seq = Totals{};
        for (const auto& f : s.frames) seq.add(f, opt.hr_solver.newton_tol);
      }
    }
    entry.frames = perf.frames();
    entry.complete = true;
    entry.hr_mean_step_s = seq.hr_s / seq.frames;
    entry.lr_mean_step_ms = seq.lr_ms / seq.frames;
    entry.embedded_error_mean_cm = seq.err_sum / double(seq.vertex_frames);
    entry.embedded_error_max_cm = seq.err_max;
    entry.max_penetration_cm = seq.pen_max;
    if (auto* e = manifest.find(perf.name))
      *e = entry;
    else
      manifest.sequences.push_back(entry);
    save_manifest(manifest_path, manifest);
    all.hr_s += seq.hr_s;
    all.lr_ms += seq.lr_ms;
    all.err_sum += seq.err_sum;
    all.vertex_frames += seq.vertex_frames;
    all.err_max = std::max(all.err_max, seq.err_max);
    all.pen_max = std::max(all.pen_max, seq.pen_max);
    all.frames += seq.frames;
    all.hr_capped += seq.hr_capped;
    ++sum.sequences;
  }
  progress.finish();
  sum.frames = all.frames;
  sum.hr_capped_frames = all.hr_capped;
  sum.hr_mean_step_s = all.hr_s / all.frames;
  sum.lr_mean_step_ms = all.lr_ms / all.frames;
  sum.hr_over_lr_time = sum.lr_mean_step_ms > 0 ? 1e3 * sum.hr_mean_step_s / sum.lr_mean_step_ms : 0;
  sum.embedded_error_mean_cm = all.err_sum / double(all.vertex_frames);
  sum.embedded_error_max_cm = all.err_max;
  sum.max_penetration_cm = all.pen_max;
  sum.wall_s = seconds_since(t0);
  return sum;
}

}  // namespace facesr
