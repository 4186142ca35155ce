#pragma once
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "sim/cl_simulator.h"
#include "sim/simulator.h"

namespace facesr {

struct SimBenchOptions {
  int frames = 60;          // steady-state frames timed per configuration (after 5 warm-up frames)
  int product_reps = 50;    // stiffness products timed
  bool sweep = true;        // lattice-size sweep on synthetic blocks
  bool cpu_reference = true;
  SolverOptions solver;
  ClSimulatorOptions cl;
  bool progress = true;
};

// Times the LR step of a model (a smooth built-in performance with warm
// start), the stiffness product, and the same on synthetic lattices of
// about 2k to 20k tets, with OpenCL and the CPU reference. Returns the JSON
// summary (see cli `bench sim --help` for keys).
nlohmann::json bench_sim(const SimModel& model, const std::vector<std::vector<float>>& frames,
                         const SimBenchOptions& opt);

// Markdown rendering of a bench_sim result for BENCHMARKS.md.
std::string sim_bench_markdown(const nlohmann::json& r);

}  // namespace facesr
