#pragma once
#include <vector>

#include "core/types.h"
#include "sim/sim_model.h"

namespace facesr {

// A spring pulling one face-surface vertex toward a target point (the
// paper's §5.3 "candy cane" on the lip corner). Stiffness in kPa·cm (force per cm).
struct PointSpring {
  int vertex = -1;
  Vec3 target = Vec3::Zero();  // cm, in the simulation mesh's rest frame
  double stiffness = 0;
};

// A kinematic sphere pushing the face surface by a penalty force
// k·(radius − distance) along the outward normal. Stiffness in kPa·cm.
struct SphereCollider {
  Vec3 centre = Vec3::Zero();
  double radius = 0;
  double stiffness = 0;
};

// Blendshape weights from capture overshoot [0, 1] a little (ARKit's
// EyeLookIn reaches 1.05): weights in [1 − kWeightTolerance, kWeightTolerance]
// are clamped into [0, 1] by the Live Link import (unless strict) and by the
// runtime's setters; beyond that, or NaN, they are refused.
constexpr double kWeightTolerance = 1.1;

// Per-frame inputs of a simulation.
struct Controls {
  std::vector<float> weights;  // one per rig blendshape (rig order), each in [0, 1]
  // Optional direct muscle activations (one per rig muscle, each in [0, 1]);
  // when given they replace the weight → activation table.
  std::vector<float> activations;
  // Explicit rigid jaw transform x' = R x + t (rest frame, cm); otherwise the
  // jaw follows the jaw blendshape weights.
  bool jaw_override = false;
  Mat3 jaw_R = Mat3::Identity();
  Vec3 jaw_t = Vec3::Zero();
  std::vector<PointSpring> springs;
  std::vector<SphereCollider> spheres;
};

// Rejects NaN, infinite or out-of-range controls with an Error that names the
// offending control (e.g. "weight 'jawOpen' is NaN").
void validate_controls(const SimModel& model, const Controls& c);

// What the solvers consume, derived from validated controls.
struct FrameInputs {
  std::vector<double> muscle_activation;  // per muscle, clamped to [0, 1]
  Mat3 jaw_R = Mat3::Identity();           // jaw nodes: x = jaw_R X + jaw_t
  Vec3 jaw_t = Vec3::Zero();
  std::vector<double> target;  // vertex × 3: track target (surface rest + blendshape offsets)
  std::vector<double> spring_k;  // vertex: point-spring stiffness, 0 if none
  std::vector<double> spring_target;  // vertex × 3
  std::vector<SphereCollider> spheres;
};

// Activations: a_m = clamp(Σ_b w_b · activation[b, m], 0, 1).
std::vector<double> muscle_activations(const SimModel& model, const std::vector<float>& weights);
// Rigid jaw motion from the weights: the jawOpen hinge plus the other jaw
// shapes' rotations (summed as rotation vectors about the pivot) and offsets.
void jaw_transform(const Jaw& jaw, const std::vector<std::string>& shape_names, const std::vector<float>& weights,
                   Mat3& R, Vec3& t);
FrameInputs prepare_frame(const SimModel& model, const Controls& c);

// Prescribed positions of the bone-attached nodes for a frame (node × 3; free nodes keep rest).
void dirichlet_positions(const SimModel& model, const FrameInputs& in, std::vector<double>& x);

}  // namespace facesr
