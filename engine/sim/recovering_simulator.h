#pragma once
#include <memory>

#include "sim/simulator.h"

namespace facesr {

// Wraps any simulator (CPU or OpenCL, LR or HR) with divergence detection
// and recovery, so that no caller ever gets a broken state reported as a
// frame (see SolverOptions::recover for the criteria). On a diverged frame
// it solves again:
//   1. from the last good state, without the warm-start extrapolation;
//   2. in recovery_substeps control sub-steps from the last good frame's
//      controls to this frame's (weights, activations, jaw, spring and sphere
//      stiffnesses ramped linearly);
//   3. as 2 with the accurate preset's iteration caps and twice the sub-steps;
//   4. from the rest pose with the accurate preset's caps.
// If all fail it returns to the last good state (its nodes and surface are
// what the caller reads) with StepStatus::Diverged.
// The factories make_cpu_simulator and make_cl_simulator apply it when
// SolverOptions::recover is set (the default).
std::unique_ptr<Simulator> make_recovering_simulator(std::unique_ptr<Simulator> inner);

}  // namespace facesr
