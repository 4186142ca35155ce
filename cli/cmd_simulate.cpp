// facesr simulate: runs a performance through the LR or HR simulator and
// writes the per-frame node positions and embedded face surface (.fsq).
// facesr bench sim: timing of the LR step (see engine/bench/sim_bench.h).
#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "bench/bench_report.h"
#include "bench/robustness_bench.h"
#include "bench/sim_bench.h"
#include "arg_lists.h"
#include "commands.h"
#include "collide/mouth_collider.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "core/progress.h"
#include "perf/livelink_csv.h"
#include "perf/perf_controls.h"
#include "perf/performance.h"
#include "perf/sequence_io.h"
#include "rig/rig_io.h"
#include "sim/cl_simulator.h"
#include "sim/simulator.h"

namespace facesr::cli {
namespace {

struct SolverArgs {
  std::string preset = "accurate";
  double newton_tol = -1, cg_tol = -1;
  int newton_max = -1, cg_max = -1;
  std::string device;
  bool cpu = false;
  bool single = false;

  void add(CLI::App* sub) {
    sub->add_option("--solver", preset, "accurate (default) | realtime (capped iterations, for games)");
    sub->add_option("--newton-tol", newton_tol, "Newton relative residual tolerance");
    sub->add_option("--newton-max", newton_max, "Newton iteration cap per frame");
    sub->add_option("--cg-tol", cg_tol, "CG relative residual tolerance per Newton step");
    sub->add_option("--cg-max", cg_max, "CG iteration cap per Newton step");
    sub->add_option("--device", device, "OpenCL device: index, name, cpu or gpu (default: first CPU device)");
    sub->add_flag("--cpu", cpu, "Use the CPU reference simulator instead of OpenCL");
    sub->add_flag("--single", single, "Single precision on the OpenCL device");
  }
  SolverOptions options() const {
    SolverOptions o;
    if (preset == "realtime") {
      o = realtime_solver();
    } else {
      require(preset == "accurate", "unknown --solver '" + preset + "' (expected accurate or realtime)");
    }
    if (newton_tol >= 0) o.newton_tol = newton_tol;
    if (cg_tol >= 0) o.cg_tol = cg_tol;
    if (newton_max >= 0) o.newton_max = newton_max;
    if (cg_max >= 0) o.cg_max = cg_max;
    require(o.newton_tol > 0 && o.cg_tol > 0 && o.newton_max > 0 && o.cg_max > 0,
            "solver tolerances and iteration caps must be positive");
    return o;
  }
  ClSimulatorOptions cl() const {
    ClSimulatorOptions c;
    c.device = compute::DeviceSelector::parse(device);
    c.single_precision = single;
    return c;
  }
  std::unique_ptr<Simulator> make(const SimModel& m) const {
    return cpu ? make_cpu_simulator(m, options()) : make_cl_simulator(m, options(), cl());
  }
};

// A Live Link CSV's repairs are warned about on stderr even with --quiet: they change the motion.
Performance load_perf(const std::string& path, const std::string& builtin, bool strict, const Rig& rig) {
  require(path.empty() != builtin.empty(), "give exactly one of --performance FILE or --builtin NAME");
  if (path.empty()) return builtin_performance(builtin, rig.blendshape_names);
  LiveLinkOptions o;
  o.strict = strict;
  return load_performance_warned(path, rig.blendshape_names, o, "simulate");
}

void require_parent(const std::string& out) {
  const auto parent = std::filesystem::path(out).parent_path();
  require(parent.empty() || std::filesystem::is_directory(parent),
          "output folder '" + parent.string() + "' does not exist");
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out(1);
  for (char ch : s) {
    if (ch == sep)
      out.emplace_back();
    else
      out.back().push_back(ch);
  }
  return out;
}

double number(const std::string& text, const std::string& what) {
  try {
    size_t used = 0;
    const double v = std::stod(text, &used);
    if (used == text.size() && std::isfinite(v)) return v;
  } catch (const std::exception&) {
  }
  throw Error(what + ": '" + text + "' is not a finite number");
}

Vec3 vec3(const std::string& text, const std::string& what) {
  const auto p = split(text, ',');
  require(p.size() == 3, what + ": expected x,y,z, got '" + text + "'");
  return Vec3(number(p[0], what), number(p[1], what), number(p[2], what));
}

// --spring VERTEX:DX,DY,DZ:K, VERTEX a face-surface index or a landmark name;
// the target is the vertex's rest position (mesh frame) plus the offset, cm.
PointSpring parse_spring(const std::string& spec, const Rig& rig, const SimModel& m) {
  const std::string what = "--spring '" + spec + "'";
  const auto p = split(spec, ':');
  require(p.size() == 3, what + ": expected VERTEX:DX,DY,DZ:STIFFNESS");
  PointSpring s;
  for (size_t i = 0; i < rig.landmark_names.size(); ++i)
    if (rig.landmark_names[i] == p[0]) s.vertex = rig.landmark_vertex[i];
  if (s.vertex < 0) {
    const double v = number(p[0], what + " (vertex is neither a landmark name nor an index)");
    require(v >= 0 && v < m.num_surface && v == std::floor(v), what + ": vertex index out of range");
    s.vertex = int(v);
  }
  s.target = Vec3(&m.surf_rest[3 * size_t(s.vertex)]) + vec3(p[1], what);
  s.stiffness = number(p[2], what);
  require(s.stiffness >= 0, what + ": stiffness must be >= 0");
  return s;
}

// --sphere X,Y,Z:RADIUS:K in the mesh frame, cm.
SphereCollider parse_sphere(const std::string& spec) {
  const std::string what = "--sphere '" + spec + "'";
  const auto p = split(spec, ':');
  require(p.size() == 3, what + ": expected X,Y,Z:RADIUS:STIFFNESS");
  SphereCollider s{vec3(p[0], what), number(p[1], what), number(p[2], what)};
  require(s.radius > 0 && s.stiffness >= 0, what + ": radius must be > 0 and stiffness >= 0");
  return s;
}

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(std::ceil(q * double(v.size())) - 1))];
}

}  // namespace

void register_simulate(CLI::App& app) {
  struct Args {
    std::string rig, res = "low", performance, builtin, out;
    std::vector<std::string> springs, spheres;
    int max_frames = 0;
    bool json = false, quiet = false, no_collisions = false, strict = false;
    double contact_stiffness = -1;
    SolverArgs solver;
  };
  static Args a;
  auto* sub = app.add_subcommand("simulate", "Run a performance through the quasistatic muscle simulator");
  sub->add_flag("--no-collisions", a.no_collisions,
                "HR: do not resolve lip-lip and lip-teeth contact (penetration is still measured)");
  sub->add_option("--contact-stiffness", a.contact_stiffness,
                  "HR: contact penalty per unit skin area, kPa/cm (default 3000)");
  sub->add_option("--rig", a.rig, "Rig file (from `facesr rig build`)")->required();
  sub->add_option("--res", a.res, "low (LR lattice, real-time) | high (HR conforming mesh)");
  sub->add_option("--performance", a.performance, "Performance: keyframe JSON or Live Link Face CSV");
  sub->add_flag("--strict", a.strict,
                "Refuse a Live Link CSV the default would repair (weights outside [0, 1], tracking-lost rows, "
                "repeated times, frame-index timecodes) instead of warning");
  sub->add_option("--builtin", a.builtin, "Built-in performance: " + [] {
    std::string s;
    for (const auto& n : builtin_performance_names()) s += (s.empty() ? "" : ", ") + n;
    return s + " (and sparse-2 ... sparse-99: more takes like sparse)";
  }());
  sub->add_option("--out,-o", a.out, "Output sequence (.fsq): node positions and face surface per frame, cm")
      ->required();
  sub->add_option("--frames", a.max_frames, "Simulate only the first N frames");
  sub->add_option("--spring", a.springs,
                  "External point spring on every frame, VERTEX:DX,DY,DZ:K (VERTEX a landmark name such as "
                  "mouth_corner_L or a surface index; target = rest + offset, cm; K in kPa·cm)");
  sub->add_option("--sphere", a.spheres, "Kinematic sphere collider on every frame, X,Y,Z:RADIUS:K (cm, kPa·cm)");
  sub->add_flag("--json", a.json,
                "Print a JSON summary: frames, mean_step_ms, p95_step_ms, mean_newton_iters, mean_cg_iters, "
                "max_rel_residual, unconverged_frames, recovered_frames, diverged_frames, nan_frames, inverted_tets_max, device; "
                "exit status 1 when any frame diverged");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  a.solver.add(sub);
  add_action(sub, [] {
    require_parent(a.out);
    const Rig rig = load_rig(a.rig);
    const Performance perf = load_perf(a.performance, a.builtin, a.strict, rig);
    const Resolution res = parse_resolution(a.res);
    const SimModel model = make_sim_model(rig, res);
    std::unique_ptr<Simulator> sim;
    std::shared_ptr<MouthCollider> collider;
    if (res == Resolution::High) {
      // The HR reference runs on the CPU: Embree queries the deforming skin
      // every Newton iteration, which needs the positions on the host, and
      // the CPU solver was the faster one on this machine (BENCHMARKS.md).
      CollisionOptions co;
      if (a.contact_stiffness > 0) co.stiffness = a.contact_stiffness;
      collider = std::make_shared<MouthCollider>(rig, model, co);
      sim = make_cpu_simulator(model, a.solver.options(), collider, !a.no_collisions);
    } else {
      require(!a.no_collisions && a.contact_stiffness < 0, "collision options apply to --res high only");
      sim = a.solver.make(model);
    }
    int frames = perf.frames();
    if (a.max_frames > 0) frames = std::min(frames, a.max_frames);
    require(frames > 0, "the performance has no frames");

    SequenceHeader h;
    h.resolution = resolution_name(res);
    h.rig_checksum = rig_checksum(rig);
    h.fps = perf.fps;
    h.num_nodes = uint64_t(model.num_nodes);
    h.num_surface = uint64_t(model.num_surface);
    SequenceWriter writer(a.out, h);
    Progress progress("simulate " + std::string(resolution_name(res)) + " (" + sim->device() + ")", frames,
                      !a.quiet);
    std::vector<double> ms, x, s;
    std::vector<float> xf, sf;
    double newton = 0, cg = 0, max_rel = 0, max_pen = 0, contacts = 0;
    int inverted_max = 0, nan_frames = 0, unconverged = 0, diverged = 0, recovered = 0, first_diverged = -1;
    Controls c;
    for (const auto& spec : a.springs) c.springs.push_back(parse_spring(spec, rig, model));
    for (const auto& spec : a.spheres) c.spheres.push_back(parse_sphere(spec));
    for (int f = 0; f < frames; ++f) {
      frame_controls(perf, f, rig.jaw, c);
      const StepStats st = sim->step(c);
      sim->nodes(x);
      sim->surface(s);
      bool finite = std::isfinite(st.rel_residual);
      for (double v : x) finite = finite && std::isfinite(v);
      if (!finite) {
        ++nan_frames;
        // A NaN frame is never written: the writer's temp file is discarded.
        throw Error("frame " + std::to_string(f) + ": the simulation produced non-finite positions; nothing written");
      }
      xf.assign(x.begin(), x.end());
      sf.assign(s.begin(), s.end());
      writer.add_frame(perf.time(f), xf.data(), sf.data());
      ms.push_back(st.ms);
      newton += st.newton_iters;
      cg += st.cg_iters;
      max_rel = std::max(max_rel, st.rel_residual);
      inverted_max = std::max(inverted_max, st.inverted_tets);
      unconverged += st.status == StepStatus::Unconverged;
      recovered += st.status == StepStatus::Recovered;
      if (st.status == StepStatus::Diverged && diverged++ == 0) first_diverged = f;
      max_pen = std::max(max_pen, st.max_penetration_cm);
      contacts += st.contacts;
      char detail[200];
      std::snprintf(detail, sizeof detail, "%.1f ms, %d Newton, %d CG, residual %.1e%s", st.ms, st.newton_iters,
                    st.cg_iters, st.rel_residual,
                    st.status == StepStatus::Diverged ? ", DIVERGED (held)" : st.status == StepStatus::Recovered ? ", recovered" : "");
      if (collider)
        std::snprintf(detail + std::strlen(detail), sizeof detail - std::strlen(detail),
                      ", %d contacts, max penetration %.3f cm", st.contacts, st.max_penetration_cm);
      progress.update(f + 1, detail);
    }
    writer.commit();
    progress.finish();
    double mean = 0;
    for (double v : ms) mean += v / frames;
    nlohmann::json j{{"frames", frames},
                     {"mean_step_ms", mean},
                     {"p95_step_ms", percentile(ms, 0.95)},
                     {"mean_newton_iters", newton / frames},
                     {"mean_cg_iters", cg / frames},
                     {"max_rel_residual", max_rel},
                     {"unconverged_frames", unconverged},
                     {"nan_frames", nan_frames},
                     {"diverged_frames", diverged},
                     {"recovered_frames", recovered},
                     {"inverted_tets_max", inverted_max},
                     {"device", sim->device()},
                     {"res", resolution_name(res)},
                     {"tets", model.num_tets},
                     {"nodes", model.num_nodes},
                     {"surface_vertices", model.num_surface},
                     {"out", a.out},
                     {"units", "cm"}};
    if (collider) {
      j["max_penetration_cm"] = max_pen;
      j["contacts_mean"] = contacts / frames;
      j["collisions_resolved"] = !a.no_collisions;
      j["collision_region_nodes"] = collider->info().region_nodes;
      j["collision_rest_excluded"] = collider->info().rest_excluded;
      j["teeth_closed"] = collider->info().teeth_closed;
    }
    if (a.json) {
      std::printf("%s\n", j.dump(2).c_str());
    } else {
      std::printf("wrote %s: %d frames, %.1f ms/frame (p95 %.1f), %.1f Newton and %.0f CG iterations per frame, "
                  "max residual %.1e, positions in cm\n",
                  a.out.c_str(), frames, mean, percentile(ms, 0.95), newton / frames, cg / frames, max_rel);
    }
    // The sequence holds only sane states (a diverged frame repeats the last
    // good one), but a take that did not play as asked is not a success.
    if (diverged > 0)
      throw Error(std::to_string(diverged) + " of " + std::to_string(frames) + " frames diverged and were held at the last good state (first: frame " +
                  std::to_string(first_diverged) + "); see diverged_frames");
  });
}

namespace {

std::string robustness_markdown(const nlohmann::json& heads, const std::string& res, const std::string& preset,
                                const std::string& device, int extreme_frames) {
  std::ostringstream md;
  md << "Robustness run (`facesr bench robustness`, " << res << " resolution, " << preset << " preset, " << device
     << "), " << machine_description() << ", " << heads.size() << " rigs; per rig every performance from rest: "
     << "the Live Link takes, the built-ins and " << extreme_frames << " extreme control frames.\n\n"
     << "| rig | frames | unconverged | recovered | diverged | NaN | max inverted tets | max rel. residual | mean ms | p95 ms |\n"
     << "|---|---|---|---|---|---|---|---|---|---|\n";
  RobustnessRow all;
  std::vector<RobustnessRow> totals;
  char line[400];
  for (const auto& h : heads) {
    const auto& t = h["total"];
    RobustnessRow r;
    r.frames = t["frames"];
    r.unconverged = t["unconverged_frames"];
    r.recovered = t["recovered_frames"];
    r.diverged = t["diverged_frames"];
    r.nan_frames = t["nan_frames"];
    r.inverted_max = t["inverted_tets_max"];
    r.max_rel_residual = t["max_rel_residual"];
    r.mean_step_ms = t["mean_step_ms"];
    r.p95_step_ms = t["p95_step_ms"];
    totals.push_back(r);
    std::snprintf(line, sizeof line, "| %s | %d | %d | %d | %d | %d | %d | %.2g | %.1f | %.1f |\n",
                  h["rig"].get<std::string>().c_str(), r.frames, r.unconverged, r.recovered, r.diverged, r.nan_frames,
                  r.inverted_max, r.max_rel_residual, r.mean_step_ms, r.p95_step_ms);
    md << line;
  }
  const RobustnessRow t = robustness_total(totals);
  std::snprintf(line, sizeof line, "| **all** | %d | %d | %d | **%d** | **%d** | %d | %.2g | %.1f | %.1f |\n\n", t.frames,
                t.unconverged, t.recovered, t.diverged, t.nan_frames, t.inverted_max, t.max_rel_residual,
                t.mean_step_ms, t.p95_step_ms);
  md << line;
  return md.str();
}

}  // namespace

void register_bench(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Benchmarks (results can be written into BENCHMARKS.md)");
  bench->require_subcommand(1);
  add_bench_runtime(bench);
  add_bench_contexts(bench);
  {
    struct RArgs {
      std::vector<std::string> rigs, takes;
      std::string builtins = "all", res = "low", results, markdown;
      int extreme_frames = 1000, max_frames = 0;
      unsigned seed = 1;
      bool json = false, quiet = false;
      SolverArgs solver;
    };
    static RArgs r;
    auto* sub = bench->add_subcommand(
        "robustness", "Every rig × every take, built-in and extreme control frame: unconverged, recovered, diverged and "
                      "NaN frames, inverted tets, residuals, step times");
    sub->add_option("--rig", r.rigs, "Rig files (one or more)")->required();
    sub->add_option("--performance", r.takes, "Performance files (Live Link CSV read leniently, with warnings)");
    sub->add_option("--builtins", r.builtins, "Comma-separated built-in performances, 'all' (default) or 'none'");
    sub->add_option("--extreme-frames", r.extreme_frames, "Extreme control frames per rig (default 1000; 0: none)");
    sub->add_option("--seed", r.seed, "Seed of the extreme frames (default 1)");
    sub->add_option("--res", r.res, "low (default) | high (CPU reference with Embree contacts)");
    sub->add_option("--max-frames", r.max_frames, "At most this many frames of each --performance file (0: all)");
    sub->add_option("--results", r.results,
                    "Folder keeping each rig's result as <rig file name>.json; a rig whose result is there is not run again");
    sub->add_option("--markdown", r.markdown, "Write the table into this Markdown file (e.g. BENCHMARKS.md)");
    sub->add_flag("--json", r.json, "Print every rig's rows (per performance and total) as JSON");
    sub->add_flag("--quiet,-q", r.quiet, "No progress output");
    r.solver.add(sub);
    add_action(sub, [] {
      require(r.extreme_frames >= 0 && r.max_frames >= 0, "--extreme-frames and --max-frames must be >= 0");
      const Resolution res = parse_resolution(r.res);
      if (!r.results.empty()) std::filesystem::create_directories(r.results);
      nlohmann::json heads = nlohmann::json::array();
      std::string device;
      for (size_t k = 0; k < r.rigs.size(); ++k) {
        const std::string& rig_path = r.rigs[k];
        const std::string cache =
            r.results.empty() ? "" : r.results + "/" + std::filesystem::path(rig_path).filename().string() + ".json";
        if (!cache.empty() && std::filesystem::exists(cache)) {
          std::ifstream in(cache);
          heads.push_back(nlohmann::json::parse(in));
          if (!r.quiet) std::fprintf(stderr, "[robustness] %s: result kept from %s\n", rig_path.c_str(), cache.c_str());
          continue;
        }
        const Rig rig = load_rig(rig_path);
        std::vector<Performance> perfs;
        for (const auto& t : r.takes) {
          Performance p = load_performance_warned(t, rig.blendshape_names, LiveLinkOptions{}, "robustness");
          if (r.max_frames > 0 && p.frames() > r.max_frames) p.weights.resize(size_t(r.max_frames) * p.names.size());
          perfs.push_back(std::move(p));
        }
        std::vector<std::string> names;
        if (r.builtins == "all") names = builtin_performance_names();
        else if (r.builtins != "none") names = split_list(r.builtins);
        for (const auto& n : names) perfs.push_back(builtin_performance(n, rig.blendshape_names));
        if (r.extreme_frames > 0)
          perfs.push_back(robustness_extreme_frames(rig.blendshape_names, r.extreme_frames, r.seed));
        const SimModel model = make_sim_model(rig, res);
        std::unique_ptr<Simulator> sim;
        if (res == Resolution::High) {
          auto collider = std::make_shared<MouthCollider>(rig, model, CollisionOptions{});
          sim = make_cpu_simulator(model, r.solver.options(), collider, true);
        } else {
          sim = r.solver.make(model);
        }
        device = sim->device();
        long total = 0;
        for (const auto& p : perfs) total += p.frames();
        Progress progress("robustness " + rig.name + " (" + std::to_string(k + 1) + "/" + std::to_string(r.rigs.size()) + ")",
                          total, !r.quiet);
        long done = 0;
        const auto rows = run_robustness(*sim, rig, perfs, 0,
                                         [&](const std::string& name) { progress.update(++done, name); });
        progress.finish();
        // Heads made from one source share its rig name: label them by file.
        nlohmann::json h = {{"rig", std::filesystem::path(rig_path).stem().string()}, {"rig_name", rig.name}, {"rig_file", rig_path}, {"res", r.res}, {"solver_preset", r.solver.preset},
                            {"device", device}, {"total", robustness_total(rows).to_json()}, {"units", "cm, ms"}};
        h["performances"] = nlohmann::json::array();
        for (const auto& row : rows) h["performances"].push_back(row.to_json());
        if (!cache.empty())
          write_file_atomically(cache, [&](std::ostream& out) { out << h.dump(2) << "\n"; });
        heads.push_back(h);
      }
      if (!r.markdown.empty())
        update_markdown_section(r.markdown, "bench-robustness-" + r.res + "-" + r.solver.preset + "-" + machine_slug(),
                                robustness_markdown(heads, r.res, r.solver.preset, device.empty() ? "cached results" : device,
                                                    r.extreme_frames));
      int diverged = 0, nan = 0;
      for (const auto& h : heads) diverged += h["total"]["diverged_frames"].get<int>(), nan += h["total"]["nan_frames"].get<int>();
      nlohmann::json j = {{"rigs", heads.size()}, {"diverged_frames", diverged}, {"nan_frames", nan}, {"heads", heads}};
      if (r.json)
        std::printf("%s\n", j.dump(2).c_str());
      else
        std::printf("%s", robustness_markdown(heads, r.res, r.solver.preset, device, r.extreme_frames).c_str());
      require(diverged == 0 && nan == 0, std::to_string(diverged) + " diverged and " + std::to_string(nan) +
                                             " NaN frames over the corpus");
    });
  }
  struct Args {
    std::string rig, res = "low", builtin = "talk", markdown;
    int frames = 60;
    bool json = false, quiet = false, no_sweep = false, no_cpu = false;
    SolverArgs solver;
  };
  static Args a;
  auto* sub = bench->add_subcommand("sim", "Steady-state ms per LR frame, stiffness-product cost, lattice-size sweep");
  sub->add_option("--rig", a.rig, "Rig file")->required();
  sub->add_option("--res", a.res, "low | high");
  sub->add_option("--builtin", a.builtin, "Built-in performance to drive the rig (default talk)");
  sub->add_option("--frames", a.frames, "Timed frames per configuration (default 60)");
  sub->add_option("--markdown", a.markdown, "Write the results into this Markdown file (e.g. BENCHMARKS.md)");
  sub->add_flag("--no-sweep", a.no_sweep, "Skip the synthetic lattice-size sweep");
  sub->add_flag("--no-cpu", a.no_cpu, "Skip the CPU reference");
  sub->add_flag("--json", a.json, "Print the results as JSON");
  sub->add_flag("--quiet,-q", a.quiet, "No progress output");
  a.solver.add(sub);
  add_action(sub, [] {
    require(a.frames > 0, "--frames must be positive");
    const Rig rig = load_rig(a.rig);
    const SimModel model = make_sim_model(rig, parse_resolution(a.res));
    const Performance perf = builtin_performance(a.builtin, rig.blendshape_names);
    std::vector<std::vector<float>> frames;
    for (int f = 0; f < perf.frames(); ++f) frames.emplace_back(perf.frame(f), perf.frame(f) + perf.names.size());
    SimBenchOptions o;
    o.frames = a.frames;
    o.sweep = !a.no_sweep;
    o.cpu_reference = !a.no_cpu;
    o.solver = a.solver.options();
    o.cl = a.solver.cl();
    o.progress = !a.quiet;
    nlohmann::json r = bench_sim(model, frames, o);
    r["rig"] = rig.name;
    r["solver_preset"] = a.solver.preset;
    if (!a.markdown.empty())
      update_markdown_section(a.markdown, "bench-sim-" + a.solver.preset + "-" + rig.name + "-" + machine_slug(),
                              sim_bench_markdown(r));
    if (a.json)
      std::printf("%s\n", r.dump(2).c_str());
    else
      std::printf("%s", sim_bench_markdown(r).c_str());
  });
}

}  // namespace facesr::cli
