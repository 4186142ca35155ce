#include "rig/landmarks.h"

#include "core/error.h"

namespace facesr {

std::map<std::string, int> landmarks_from_multipie68(const std::vector<int>& idx, const Points& V) {
  require(idx.size() == 68, "landmarks: expected 68 Multi-PIE landmarks, got " + std::to_string(idx.size()));
  for (int i : idx) require(i >= 0 && i < V.rows(), "landmarks: vertex index out of range");
  std::map<std::string, int> L;
  auto x = [&](int k) { return V(idx[k], 0); };
  // Pairs (a, b) of mirrored points; the one with larger x is the subject's left.
  const std::vector<std::pair<std::string, std::pair<int, int>>> pairs = {
      {"jaw_top", {0, 16}},     {"jaw_upper", {2, 14}},    {"jaw_angle", {4, 12}},
      {"jaw_lower", {6, 10}},   {"brow_outer", {17, 26}},  {"brow_mid", {19, 24}},
      {"brow_inner", {21, 22}}, {"nostril", {31, 35}},     {"eye_outer", {36, 45}},
      {"eye_inner", {39, 42}},  {"eye_top", {37, 44}},     {"eye_bottom", {41, 46}},
      {"mouth_corner", {48, 54}}, {"upper_lip_peak", {50, 52}}, {"lower_lip_side", {58, 56}}};
  for (const auto& [name, ab] : pairs) {
    const bool a_left = x(ab.first) > x(ab.second);
    L[name + "_L"] = idx[a_left ? ab.first : ab.second];
    L[name + "_R"] = idx[a_left ? ab.second : ab.first];
  }
  L["chin"] = idx[8];
  L["nasion"] = idx[27];
  L["nose_tip"] = idx[30];
  L["subnasale"] = idx[33];
  L["upper_lip_top"] = idx[51];
  L["lower_lip_bottom"] = idx[57];
  L["upper_lip_inner"] = idx[62];
  L["lower_lip_inner"] = idx[66];
  const bool eye36_left = x(36) > x(45);
  for (int k = 0; k < 6; ++k) {
    L["eye_ring_" + std::string(eye36_left ? "L_" : "R_") + std::to_string(k)] = idx[36 + k];
    L["eye_ring_" + std::string(eye36_left ? "R_" : "L_") + std::to_string(k)] = idx[42 + k];
  }
  for (int k = 0; k < 12; ++k) L["mouth_ring_" + std::to_string(k)] = idx[48 + k];
  return L;
}

}  // namespace facesr
