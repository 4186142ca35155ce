#include "bench/sim_bench.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "bench/bench_report.h"
#include "core/progress.h"
#include "sim/block_model.h"

namespace facesr {

namespace {

struct Timing {
  double mean_ms = 0, p95_ms = 0, mean_newton = 0, mean_cg = 0, max_rel = 0;
  int inverted_max = 0, frames = 0, diverged = 0;
};

double percentile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, size_t(std::ceil(q * double(v.size())) - 1))];
}

Timing run_frames(Simulator& sim, const std::vector<std::vector<float>>& frames, int count, Progress* progress,
                  long& done) {
  sim.reset();
  Controls c;
  const int warmup = std::min<int>(5, int(frames.size()) - 1);
  std::vector<double> ms;
  Timing t;
  for (int f = 0; f < warmup + count; ++f) {
    c.weights = frames[size_t(f) % frames.size()];
    const StepStats st = sim.step(c);
    if (progress) progress->update(++done);
    t.diverged += st.status == StepStatus::Diverged;
    if (f < warmup) continue;
    ms.push_back(st.ms);
    t.mean_newton += st.newton_iters;
    t.mean_cg += st.cg_iters;
    t.max_rel = std::max(t.max_rel, st.rel_residual);
    t.inverted_max = std::max(t.inverted_max, st.inverted_tets);
  }
  t.frames = count;
  for (double v : ms) t.mean_ms += v / count;
  t.p95_ms = percentile(ms, 0.95);
  t.mean_newton /= count;
  t.mean_cg /= count;
  return t;
}

nlohmann::json to_json(const Timing& t) {
  return {{"mean_step_ms", t.mean_ms},       {"p95_step_ms", t.p95_ms},
          {"mean_newton_iters", t.mean_newton}, {"mean_cg_iters", t.mean_cg},
          {"max_rel_residual", t.max_rel},   {"inverted_tets_max", t.inverted_max},
          {"diverged_frames", t.diverged}};
}

// Smooth frames for a synthetic block: its one shape and its muscle ramp.
std::vector<std::vector<float>> block_frames(int n) {
  std::vector<std::vector<float>> f;
  for (int i = 0; i < n; ++i) f.push_back({float(0.5 - 0.5 * std::cos(2 * M_PI * i / 60.0))});
  return f;
}

}  // namespace

nlohmann::json bench_sim(const SimModel& model, const std::vector<std::vector<float>>& frames,
                         const SimBenchOptions& opt) {
  // Lattice sweep sizes (cells per side), about 2k to 20k tets at 6 tets per cell.
  const std::vector<std::array<int, 3>> sweep = {{8, 8, 5}, {12, 10, 7}, {15, 14, 8}, {19, 17, 10}};
  const int nsweep = opt.sweep ? int(sweep.size()) : 0;
  const int configs = (1 + nsweep) * (opt.cpu_reference ? 2 : 1);
  long done = 0;
  Progress progress("bench sim", long(configs) * (opt.frames + 5), opt.progress);

  nlohmann::json r;
  r["machine"] = machine_description();
  r["date"] = today_iso();
  r["res"] = resolution_name(model.res);
  r["tets"] = model.num_tets;
  r["nodes"] = model.num_nodes;
  r["frames"] = opt.frames;
  r["solver"] = {{"newton_tol", opt.solver.newton_tol}, {"newton_max", opt.solver.newton_max},
                 {"cg_tol", opt.solver.cg_tol}, {"cg_max", opt.solver.cg_max}};
  r["goal_ms"] = 33.0;

  auto cl = make_cl_simulator(model, opt.solver, opt.cl);
  r["device"] = cl->device();
  const Timing tc = run_frames(*cl, frames, opt.frames, &progress, done);
  r["opencl"] = to_json(tc);
  r["opencl"]["product_ms"] = cl->time_stiffness_product(opt.product_reps);
  r["mean_step_ms"] = tc.mean_ms;
  r["p95_step_ms"] = tc.p95_ms;
  r["fps"] = tc.mean_ms > 0 ? 1000.0 / tc.mean_ms : 0.0;
  r["meets_goal"] = tc.mean_ms <= 33.0;
  if (opt.cpu_reference) {
    auto cpu = make_cpu_simulator(model, opt.solver);
    const Timing tr = run_frames(*cpu, frames, opt.frames, &progress, done);
    r["cpu_reference"] = to_json(tr);
    r["cpu_reference"]["product_ms"] = cpu->time_stiffness_product(opt.product_reps);
    r["opencl_over_cpu"] = tr.mean_ms > 0 ? tc.mean_ms / tr.mean_ms : 0.0;
  }

  nlohmann::json sizes = nlohmann::json::array();
  for (int i = 0; i < nsweep; ++i) {
    const SimModel b = make_block_model(sweep[i][0], sweep[i][1], sweep[i][2], 0.8, model.material);
    const auto bf = block_frames(opt.frames + 5);
    nlohmann::json e{{"tets", b.num_tets}, {"nodes", b.num_nodes}};
    auto bcl = make_cl_simulator(b, opt.solver, opt.cl);
    const Timing t1 = run_frames(*bcl, bf, opt.frames, &progress, done);
    e["opencl"] = to_json(t1);
    e["opencl"]["product_ms"] = bcl->time_stiffness_product(opt.product_reps);
    if (opt.cpu_reference) {
      auto bcpu = make_cpu_simulator(b, opt.solver);
      const Timing t2 = run_frames(*bcpu, bf, opt.frames, &progress, done);
      e["cpu_reference"] = to_json(t2);
      e["cpu_reference"]["product_ms"] = bcpu->time_stiffness_product(opt.product_reps);
      e["opencl_over_cpu"] = t2.mean_ms > 0 ? t1.mean_ms / t2.mean_ms : 0.0;
    }
    sizes.push_back(e);
  }
  r["sizes"] = sizes;
  progress.finish();
  return r;
}

std::string sim_bench_markdown(const nlohmann::json& r) {
  std::ostringstream md;
  char buf[512];
  md << "### LR simulation step (`facesr bench sim`)\n\n";
  md << "Measured " << r.value("date", "") << " on " << r.value("machine", "") << ", OpenCL device "
     << r.value("device", "") << ". Rig `" << r.value("rig", "") << "`, " << r.value("res", "") << " resolution, "
     << r["tets"].get<int>() << " tets, " << r["nodes"].get<int>() << " nodes; " << r["frames"].get<int>()
     << " steady-state frames of a smooth performance with warm start after 5 warm-up frames. Solver: Newton tol "
     << r["solver"]["newton_tol"].get<double>() << ", at most " << r["solver"]["newton_max"].get<int>()
     << " Newton iterations, CG tol " << r["solver"]["cg_tol"].get<double>() << ", at most "
     << r["solver"]["cg_max"].get<int>() << " CG iterations.\n\n";
  md << "| backend | mean ms/frame | p95 ms | Newton its | CG its | max rel. residual | stiffness product ms |\n";
  md << "|---|---|---|---|---|---|---|\n";
  auto row = [&](const char* name, const nlohmann::json& t) {
    std::snprintf(buf, sizeof buf, "| %s | %.1f | %.1f | %.1f | %.0f | %.1e | %.3f |\n", name,
                  t["mean_step_ms"].get<double>(), t["p95_step_ms"].get<double>(),
                  t["mean_newton_iters"].get<double>(), t["mean_cg_iters"].get<double>(),
                  t["max_rel_residual"].get<double>(), t["product_ms"].get<double>());
    md << buf;
  };
  row("OpenCL", r["opencl"]);
  if (r.contains("cpu_reference")) row("CPU reference", r["cpu_reference"]);
  const double mean = r["mean_step_ms"].get<double>();
  std::snprintf(buf, sizeof buf,
                "\nGoal: ≤ 33 ms per frame (30 FPS). Measured %.1f ms (%.1f FPS): %s.\n", mean, 1000.0 / mean,
                mean <= 33 ? "met" : "missed");
  md << buf;
  if (mean > 33) {
    std::snprintf(buf, sizeof buf, "Missed by %.1f ms (%.1f× the budget).\n", mean - 33, mean / 33);
    md << buf;
  }
  if (r.contains("opencl_over_cpu")) {
    std::snprintf(buf, sizeof buf, "OpenCL / CPU-reference time ratio: %.2f.\n", r["opencl_over_cpu"].get<double>());
    md << buf;
  }
  if (!r["sizes"].empty()) {
    md << "\nCost against lattice size (synthetic slabs of 0.8 cm cells, bottom fixed, a muscle layer and a "
          "tracked top face driven by a smooth ramp):\n\n";
    md << "| tets | nodes | OpenCL ms/frame | CPU ms/frame | OpenCL product ms | CPU product ms | CG its/frame |\n";
    md << "|---|---|---|---|---|---|---|\n";
    for (const auto& e : r["sizes"]) {
      auto cell = [&](const char* backend, const char* key, const char* fmt) {
        if (!e.contains(backend)) return std::string("-");
        char b[32];
        std::snprintf(b, sizeof b, fmt, e[backend][key].get<double>());
        return std::string(b);
      };
      std::snprintf(buf, sizeof buf, "| %d | %d | %s | %s | %s | %s | %.0f |\n", e["tets"].get<int>(),
                    e["nodes"].get<int>(), cell("opencl", "mean_step_ms", "%.1f").c_str(),
                    cell("cpu_reference", "mean_step_ms", "%.1f").c_str(),
                    cell("opencl", "product_ms", "%.3f").c_str(), cell("cpu_reference", "product_ms", "%.3f").c_str(),
                    e["opencl"]["mean_cg_iters"].get<double>());
      md << buf;
    }
  }
  return md.str();
}

}  // namespace facesr
