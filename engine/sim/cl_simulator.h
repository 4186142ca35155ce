#pragma once
#include <memory>

#include "compute/cl_device.h"
#include "sim/simulator.h"

namespace facesr {

struct ClSimulatorOptions {
  compute::DeviceSelector device;  // default: first CPU device (PoCL)
  // Single precision even where the device has fp64 (GPUs without fast
  // doubles). Devices without fp64 always run in single precision.
  bool single_precision = false;
  // Per-tet kernels (energy, gradient, Hessian): Auto runs eight tets per
  // work-item, one per vector lane, on CPU devices (PoCL leaves one-tet
  // kernels scalar) and one tet per work-item on GPUs; Simd and Scalar force
  // either, so that tests compare both on a CPU device. The stiffness
  // product is eight-wide on every device.
  enum class Elements { Auto, Simd, Scalar };
  Elements elements = Elements::Auto;
  // The CG's stiffness product: Assembled sums K once per Newton step into
  // float 3x3 blocks (sim/stiffness_pattern.h) and multiplies by it; Elements
  // recomputes every tet's product from its dP/dF each iteration and gathers
  // the corners (no assembly, a quarter of the memory). Both give the same
  // matrix up to float rounding; tests compare them.
  enum class Product { Assembled, Elements };
  Product product = Product::Assembled;
  // CG iterations enqueued between reads of the solve's stopping flags (the
  // scalar recurrences run on the device; iterations queued past the stop
  // do nothing). 0: the previous solve's count first, then 4 at a time.
  // The iterates do not depend on it (tested); 1 waits every iteration.
  int cg_batch = 0;
};

// The OpenCL simulator: the same energy (cl/fsr_material.h) and the same
// Newton / PCG / line-search algorithm as the CPU reference, with every
// per-element and vector operation in kernels (cl/sim.cl). Buffers stay on
// the device across frames; a frame uploads only its controls, and a CG
// solve reads back two flags per batch of iterations.
std::unique_ptr<Simulator> make_cl_simulator(const SimModel& model, const SolverOptions& opt = {},
                                             const ClSimulatorOptions& cl = {});

}  // namespace facesr
