#pragma once
// The runtime a game drives (capi/facesr.h is a thin C layer over this): one
// face's LR simulation (OpenCL) plus super-resolution inference, with
// controls, external springs and spheres, synchronous stepping, and a
// two-stage pipeline (frame t+1 simulates while frame t super-resolves).
// The rig and the model, compiled once into a RuntimeModel, are immutable and
// shared by every context on them; a RuntimeContext holds only its own state
// and is used by one thread at a time.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "compute/cl_device.h"
#include "rig/rig.h"
#include "sim/controls.h"
#include "sim/simulator.h"
#include "runtime/runtime_model.h"
#include "sr/sr_model.h"

namespace facesr {

struct RuntimeOptions {
  compute::DeviceSelector device;         // for the LR simulation and the inference
  SolverOptions solver = realtime_solver();
  bool cpu_inference = false;             // the C++ reference inference instead of OpenCL
  // Give the simulation and the OpenCL inference half of the device's compute
  // units each (sub-devices; see compute::DeviceSelector::parts), so that
  // pipelined stepping (step_async) runs frame t's inference and frame t+1's
  // simulation on separate cores instead of interleaving them on all of them.
  // Synchronous steps then run each stage on half the device. A device that
  // cannot be split is shared whole, as without the option.
  bool split_device = false;
  // The LR simulation in float instead of double (devices without fp64 are
  // always float). The real-time preset's tolerances are far above float
  // rounding: on ICT "talk" the embedded surface moved 0.00003 cm on
  // average (0.003 cm at most) against double and stayed as close to the
  // accurate solver's (0.00257 cm mean, both), at 12 % less time per step
  // (docs/runtime.md). Keep double for the accurate preset.
  bool lr_single_precision = true;
};

struct FrameResult {
  int64_t frame = -1;
  std::vector<float> positions;  // M × 3, cm, super-resolved surface (rest frame)
  std::vector<float> normals;    // M × 3, unit area-weighted vertex normals
  std::vector<float> embedded;   // M × 3, cm, the LR-embedded surface (rig rest + embedded displacement)
  double simulation_ms = 0, inference_ms = 0, total_ms = 0;
  int newton_iterations = 0, cg_iterations = 0;
  double relative_residual = 0;
  // The LR solve's outcome. With StepStatus::Diverged every recovery failed
  // and positions, normals and embedded are the last good frame's surface.
  StepStatus status = StepStatus::Converged;
  int inverted_tets = 0;  // LR tets with det F ≤ 0 in the returned state's solve
  int recoveries = 0;     // extra solves the recovery ladder ran
};

class RuntimeContext {
 public:
  // Throws Error when the model was trained on another rig, is not a network
  // ("sr"), or the device cannot be opened.
  RuntimeContext(std::shared_ptr<const Rig> rig, std::shared_ptr<const SrModel> model, const RuntimeOptions& opt = {});
  // A context on a compiled model: what the constructor above does less
  // compile_runtime_model, for the second and later contexts of one rig and
  // model. Throws Error when the device cannot be opened.
  RuntimeContext(std::shared_ptr<const RuntimeModel> compiled, const RuntimeOptions& opt = {});
  ~RuntimeContext();  // waits for pending frames
  RuntimeContext(const RuntimeContext&) = delete;
  RuntimeContext& operator=(const RuntimeContext&) = delete;

  const Rig& rig() const;
  const std::shared_ptr<const RuntimeModel>& compiled() const;
  int num_weights() const;
  int num_vertices() const;

  // Controls for the next step; each setter validates (Error naming the
  // control) and changes nothing on failure.
  void set_weight(int index, float value);
  void set_weight(const std::string& name, float value);
  void set_weights(const std::vector<float>& w);
  void set_jaw(const Mat3& R, const Vec3& t);  // R must be a rotation
  void clear_jaw();
  int add_spring(int vertex, const Vec3& target, double stiffness);  // returns an id > 0
  void move_spring(int id, const Vec3& target);
  void remove_spring(int id);
  int add_sphere(const Vec3& centre, double radius, double stiffness);
  void move_sphere(int id, const Vec3& centre);
  void remove_sphere(int id);
  void reset();  // rest pose, no controls, nothing pending

  // Simulate and super-resolve one frame now (Error if frames are pending).
  void step();
  // Queue a frame (controls copied); at most 2 pending (Error beyond).
  void step_async();
  // Wait for the oldest pending frame, make it the current result, return its
  // frame number; Error if nothing is pending or that frame failed.
  int64_t wait();
  int pending() const;

  // The current (latest waited-for or stepped) frame; frame -1 is the rest pose.
  const FrameResult& result() const;
  std::string device() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace facesr
