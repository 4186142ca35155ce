// Evaluation statistics: per-vertex error, summary statistics and the paper's
// table 1 normalisation, on cases computed by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "eval/error_stats.h"
#include "eval/table1_normalization.h"
#include "eval/vertex_error.h"
#include "test_support.h"

using namespace facesr;
using facesr::fixtures::error_of;

TEST(EvalStats, SummaryOfAnEvenAndAnOddSet) {
  const ErrorStats s = error_stats({4, 1, 3, 2});
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.median, 2.5);           // mean of the two middle values
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));  // population: (2.25 + 0.25 + 0.25 + 2.25) / 4
  EXPECT_DOUBLE_EQ(s.max, 4);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_EQ(s.count, 4);
  const ErrorStats o = error_stats({10, 0, 2});
  EXPECT_DOUBLE_EQ(o.median, 2);
  EXPECT_DOUBLE_EQ(o.mean, 4);
  EXPECT_DOUBLE_EQ(o.std, std::sqrt((36.0 + 16 + 4) / 3));
}

TEST(EvalStats, ConstantSetHasNoSpreadEvenFarFromZero) {
  const ErrorStats s = error_stats(std::vector<double>(1000, 1e6 + 0.1));
  EXPECT_LT(s.std, 1e-6);  // a one-pass E[x^2] - E[x]^2 would leave ~1e-2 here
  EXPECT_DOUBLE_EQ(s.median, 1e6 + 0.1);
}

TEST(EvalStats, EmptyOrNonFiniteIsAnError) {
  EXPECT_NE(error_of([] { error_stats({}); }).find("no values"), std::string::npos);
  EXPECT_NE(error_of([] { error_stats({1, std::nan(""), 2}); }).find("value 1"), std::string::npos);
}

TEST(EvalStats, VertexErrorIsTheDisplacementDistance) {
  // Vertex 0 off by (3, 4, 0): 5 cm; vertex 1 exact; vertex 2 off by (0, 0, -2).
  const std::vector<float> ref = {1, 1, 1, 0, 0, 0, 0.5f, 0.5f, 0.5f};
  const std::vector<float> pred = {4, 5, 1, 0, 0, 0, 0.5f, 0.5f, -1.5f};
  const std::vector<double> d = vertex_error(pred, ref);
  ASSERT_EQ(d.size(), 3u);
  EXPECT_DOUBLE_EQ(d[0], 5);
  EXPECT_DOUBLE_EQ(d[1], 0);
  EXPECT_DOUBLE_EQ(d[2], 2);
  EXPECT_DOUBLE_EQ(frame_mean_error(pred, ref), 7.0 / 3);
}

TEST(EvalStats, VertexErrorRejectsMismatchedOrBadArrays) {
  const std::vector<float> a(6, 0.f), b(9, 0.f), c = {0, 0, 0, 0, std::numeric_limits<float>::infinity(), 0};
  EXPECT_NE(error_of([&] { vertex_error(a, b, "method x"); }).find("method x"), std::string::npos);
  EXPECT_NE(error_of([&] { vertex_error(std::vector<float>(4), std::vector<float>(4)); }).find("M x 3"),
            std::string::npos);
  EXPECT_NE(error_of([&] { vertex_error(c, a); }).find("vertex 1"), std::string::npos);
}

TEST(EvalStats, Table1DividesEveryMethodByTheLargestFrameErrorOfAny) {
  // Method A's frame means 1, 2; method B's 2, 4: the normaliser is 4 (B's worst frame).
  const std::vector<std::vector<double>> fm = {{1, 2}, {2, 4}};
  EXPECT_DOUBLE_EQ(table1_normalizer(fm), 4);
  const std::vector<ErrorStats> s = table1_normalized_stats(fm);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_DOUBLE_EQ(s[0].mean, 0.375);
  EXPECT_DOUBLE_EQ(s[0].median, 0.375);
  EXPECT_DOUBLE_EQ(s[0].std, 0.125);
  EXPECT_DOUBLE_EQ(s[0].max, 0.5);
  EXPECT_DOUBLE_EQ(s[0].min, 0.25);
  EXPECT_DOUBLE_EQ(s[1].mean, 0.75);
  EXPECT_DOUBLE_EQ(s[1].max, 1.0);  // the table's 1.00
  EXPECT_DOUBLE_EQ(s[1].min, 0.5);
  // Ratios between methods survive the normalisation.
  EXPECT_DOUBLE_EQ(s[1].mean / s[0].mean, 2);
}

TEST(EvalStats, Table1OfExactMethodsStaysZero) {
  const std::vector<ErrorStats> s = table1_normalized_stats({{0, 0}, {0, 0}});
  EXPECT_EQ(s[0].max, 0);
  EXPECT_EQ(s[1].mean, 0);
}

TEST(EvalStats, Table1RejectsEmptyAndNegative) {
  EXPECT_NE(error_of([] { table1_normalizer({}); }).find("no methods"), std::string::npos);
  EXPECT_NE(error_of([] { table1_normalizer({{1}, {}}); }).find("method 1"), std::string::npos);
  EXPECT_NE(error_of([] { table1_normalizer({{1, -1}}); }).find("frame 1"), std::string::npos);
}
