#include "sim/controls.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace facesr {

namespace {
bool finite3(const Vec3& v) { return v.allFinite(); }
}  // namespace

void validate_controls(const SimModel& m, const Controls& c) {
  require(int(c.weights.size()) == m.num_shapes,
          "controls: " + std::to_string(c.weights.size()) + " weights given, the rig has " +
              std::to_string(m.num_shapes) + " blendshapes");
  for (int b = 0; b < m.num_shapes; ++b) {
    const float w = c.weights[b];
    const std::string name = "controls: weight '" + m.shape_names[b] + "'";
    require(!std::isnan(w), name + " is NaN");
    require(std::isfinite(w), name + " is infinite");
    require(w >= 0.0f && w <= 1.0f, name + " = " + std::to_string(w) + " is outside [0, 1]");
  }
  if (!c.activations.empty()) {
    require(int(c.activations.size()) == m.num_muscles,
            "controls: " + std::to_string(c.activations.size()) + " activations given, the rig has " +
                std::to_string(m.num_muscles) + " muscles");
    for (int k = 0; k < m.num_muscles; ++k) {
      const float a = c.activations[k];
      const std::string name = "controls: activation of muscle '" + m.muscle_names[k] + "'";
      require(std::isfinite(a), name + " is not finite");
      require(a >= 0.0f && a <= 1.0f, name + " = " + std::to_string(a) + " is outside [0, 1]");
    }
  }
  if (c.jaw_override) {
    require(c.jaw_R.allFinite() && finite3(c.jaw_t), "controls: jaw transform has non-finite entries");
    const double orth = (c.jaw_R.transpose() * c.jaw_R - Mat3::Identity()).norm();
    require(orth < 1e-4 && c.jaw_R.determinant() > 0, "controls: jaw rotation is not a rotation matrix");
  }
  for (size_t i = 0; i < c.springs.size(); ++i) {
    const auto& s = c.springs[i];
    const std::string name = "controls: spring " + std::to_string(i);
    require(s.vertex >= 0 && s.vertex < m.num_surface,
            name + ": vertex " + std::to_string(s.vertex) + " is not a face-surface vertex (0.." +
                std::to_string(m.num_surface - 1) + ")");
    require(finite3(s.target), name + ": target is not finite");
    require(std::isfinite(s.stiffness) && s.stiffness >= 0, name + ": stiffness must be finite and >= 0");
  }
  for (size_t i = 0; i < c.spheres.size(); ++i) {
    const auto& s = c.spheres[i];
    const std::string name = "controls: sphere " + std::to_string(i);
    require(finite3(s.centre), name + ": centre is not finite");
    require(std::isfinite(s.radius) && s.radius >= 0, name + ": radius must be finite and >= 0");
    require(std::isfinite(s.stiffness) && s.stiffness >= 0, name + ": stiffness must be finite and >= 0");
  }
}

std::vector<double> muscle_activations(const SimModel& m, const std::vector<float>& weights) {
  std::vector<double> a(m.num_muscles, 0.0);
  for (int b = 0; b < m.num_shapes; ++b) {
    if (weights[b] == 0) continue;
    for (int k = 0; k < m.num_muscles; ++k) a[k] += double(weights[b]) * m.activation[size_t(b) * m.num_muscles + k];
  }
  for (double& v : a) v = std::clamp(v, 0.0, 1.0);
  return a;
}

void jaw_transform(const Jaw& jaw, const std::vector<std::string>& names, const std::vector<float>& weights, Mat3& R,
                   Vec3& t) {
  Vec3 omega = Vec3::Zero(), shift = Vec3::Zero();
  for (size_t b = 0; b < names.size(); ++b) {
    const double w = weights[b];
    if (w == 0) continue;
    if (names[b] == "jawOpen") {
      omega += w * jaw.open_angle_deg * M_PI / 180.0 * jaw.axis.normalized();
      continue;
    }
    for (const auto& s : jaw.shapes) {
      if (s.name != names[b]) continue;
      const Eigen::AngleAxisd aa(s.R);
      omega += w * aa.angle() * aa.axis();
      // Offset of the pivot under this shape's rigid motion.
      shift += w * (s.R * jaw.pivot + s.t - jaw.pivot);
    }
  }
  const double angle = omega.norm();
  R = angle > 0 ? Mat3(Eigen::AngleAxisd(angle, omega / angle)) : Mat3::Identity();
  // x' = R (x − p) + p + shift
  t = jaw.pivot - R * jaw.pivot + shift;
}

FrameInputs prepare_frame(const SimModel& m, const Controls& c) {
  validate_controls(m, c);
  FrameInputs in;
  if (c.activations.empty())
    in.muscle_activation = muscle_activations(m, c.weights);
  else
    in.muscle_activation.assign(c.activations.begin(), c.activations.end());
  if (c.jaw_override) {
    in.jaw_R = c.jaw_R;
    in.jaw_t = c.jaw_t;
  } else {
    jaw_transform(m.jaw, m.shape_names, c.weights, in.jaw_R, in.jaw_t);
  }
  in.target = m.surf_rest;
  for (int b = 0; b < m.num_shapes; ++b) {
    const double w = c.weights[b];
    if (w == 0) continue;
    const float* d = &m.shape_deltas[size_t(b) * 3 * m.num_surface];
    for (size_t i = 0; i < in.target.size(); ++i) in.target[i] += w * d[i];
  }
  in.spring_k.assign(m.num_surface, 0.0);
  in.spring_target.assign(3 * size_t(m.num_surface), 0.0);
  for (const auto& s : c.springs) {
    // Several springs on one vertex combine into one with the stiffness-weighted target.
    const double k0 = in.spring_k[s.vertex], k = k0 + s.stiffness;
    if (k <= 0) continue;
    for (int d = 0; d < 3; ++d)
      in.spring_target[3 * s.vertex + d] = (k0 * in.spring_target[3 * s.vertex + d] + s.stiffness * s.target[d]) / k;
    in.spring_k[s.vertex] = k;
  }
  for (const auto& s : c.spheres)
    if (s.radius > 0 && s.stiffness > 0) in.spheres.push_back(s);
  return in;
}

void dirichlet_positions(const SimModel& m, const FrameInputs& in, std::vector<double>& x) {
  for (int v = 0; v < m.num_nodes; ++v) {
    if (m.node_bone[v] == 0) continue;
    const Vec3 X(m.rest[3 * v], m.rest[3 * v + 1], m.rest[3 * v + 2]);
    const Vec3 p = m.node_bone[v] == 2 ? Vec3(in.jaw_R * X + in.jaw_t) : X;
    for (int k = 0; k < 3; ++k) x[3 * v + k] = p[k];
  }
}

}  // namespace facesr
