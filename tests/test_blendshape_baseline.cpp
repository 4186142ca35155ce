// The linear blendshape baseline on a planted case: its surface is exactly
// Σ w_i δ_i of the rig's deltas, in the weights' own order.
#include <gtest/gtest.h>

#include "baselines/blendshape.h"
#include "test_support.h"

namespace facesr {
namespace {

TEST(BlendshapeBaseline, IsTheWeightedSumOfTheRigsDeltasInTheNamedOrder) {
  Rig rig;
  rig.name = "planted";
  rig.surface.resize(2, 3);
  rig.surface.setZero();
  rig.blendshape_names = {"a", "b", "c"};
  // Shape s moves vertex v by (s+1, v, -s) cm.
  for (int s = 0; s < 3; ++s)
    for (int v = 0; v < 2; ++v)
      for (float x : {float(s + 1), float(v), float(-s)}) rig.blendshape_deltas.push_back(x);
  const BlendshapeBaseline b(rig, {"c", "a"});  // "b" not named: stays 0
  std::vector<float> out(6);
  b.apply({0.5f, 2.0f}, out.data());
  // 0.5 δ_c + 2 δ_a: vertex 0 = 0.5(3, 0, -2) + 2(1, 0, 0) = (3.5, 0, -1); vertex 1 adds (0, 2.5, 0).
  const std::vector<float> want{3.5f, 0, -1, 3.5f, 2.5f, -1};
  for (int k = 0; k < 6; ++k) EXPECT_FLOAT_EQ(out[size_t(k)], want[size_t(k)]) << k;
  b.apply({0, 0}, out.data());
  for (float x : out) EXPECT_EQ(x, 0);
  EXPECT_NE(fixtures::error_of([&] { b.apply({1}, out.data()); }).find("1 weights, expected 2"), std::string::npos);
  EXPECT_NE(fixtures::error_of([&] { BlendshapeBaseline(rig, {"zz"}); }).find("no shape 'zz'"), std::string::npos);
}

}  // namespace
}  // namespace facesr
