// The frame-wise error CSV and the fig. 5 SVG plot: written atomically,
// parseable, one row per frame and one polyline per method.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "eval/frame_error_csv.h"
#include "eval/frame_error_svg.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

struct Table {
  std::vector<FrameId> frames;
  std::vector<std::string> methods;
  std::vector<std::vector<double>> means;
};

Table sample() {
  Table t;
  for (int f = 0; f < 5; ++f) t.frames.push_back({"anger", f});
  for (int f = 0; f < 4; ++f) t.frames.push_back({"fear", 10 + f});
  t.methods = {"ours", "embedded", "rbf, tuned"};
  for (size_t m = 0; m < t.methods.size(); ++m) {
    t.means.emplace_back();
    for (size_t f = 0; f < t.frames.size(); ++f) t.means.back().push_back(0.1 * double(m + 1) + 0.01 * double(f));
  }
  return t;
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string l; std::getline(in, l);) lines.push_back(l);
  return lines;
}

size_t count(const std::string& hay, const std::string& needle) {
  size_t n = 0;
  for (size_t p = hay.find(needle); p != std::string::npos; p = hay.find(needle, p + 1)) ++n;
  return n;
}

class EvalOutputs : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("facesr_eval_outputs_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& n) const { return (dir_ / n).string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(EvalOutputs, CsvHasAHeaderInCmAndOneRowPerFrame) {
  const Table t = sample();
  write_frame_error_csv(path("f.csv"), t.frames, t.methods, t.means);
  const std::vector<std::string> lines = lines_of(path("f.csv"));
  ASSERT_EQ(lines.size(), t.frames.size() + 1);
  EXPECT_EQ(lines[0], "sequence,frame,ours_mean_cm,embedded_mean_cm,\"rbf, tuned_mean_cm\"");
  EXPECT_EQ(lines[1], "anger,0,0.1,0.2,0.3");
  EXPECT_EQ(lines[6].substr(0, 8), "fear,10,");
  // Parse back the numbers of the last row.
  std::stringstream row(lines.back());
  std::string seq, frame, a, b;
  std::getline(row, seq, ',');
  std::getline(row, frame, ',');
  std::getline(row, a, ',');
  std::getline(row, b, ',');
  EXPECT_EQ(seq, "fear");
  EXPECT_EQ(std::stoi(frame), 13);
  EXPECT_NEAR(std::stod(a), 0.18, 1e-12);
  EXPECT_NEAR(std::stod(b), 0.28, 1e-12);
  // Nothing but the file itself is left in the folder (no temporaries).
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(EvalOutputs, CsvRejectsMismatchedTablesWithoutWriting) {
  Table t = sample();
  t.means[1].pop_back();
  EXPECT_NE(fixtures::error_of([&] {
              write_frame_error_csv(path("f.csv"), t.frames, t.methods, t.means);
            }).find("'embedded'"),
            std::string::npos);
  t = sample();
  t.means[2][3] = std::nan("");
  EXPECT_NE(
      fixtures::error_of([&] { write_frame_error_csv(path("f.csv"), t.frames, t.methods, t.means); }).find("frame 3"),
      std::string::npos);
  EXPECT_FALSE(fs::exists(path("f.csv")));
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(EvalOutputs, SvgHasOnePolylinePerMethodAxesLegendAndTitle) {
  const Table t = sample();
  write_frame_error_svg(path("f.svg"), t.frames, t.methods, t.means, "Errors <test> & more");
  std::ifstream in(path("f.svg"));
  const std::string svg((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(svg.rfind("<?xml", 0), 0u);
  EXPECT_EQ(count(svg, "<svg"), 1u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_EQ(count(svg, "<polyline"), t.methods.size());
  EXPECT_EQ(count(svg, "</polyline>"), t.methods.size());
  // Each polyline has one point per frame.
  const size_t p = svg.find("points=\"");
  const std::string pts = svg.substr(p + 8, svg.find('"', p + 8) - p - 8);
  EXPECT_EQ(count(pts, ","), t.frames.size());
  EXPECT_NE(svg.find("Errors &lt;test&gt; &amp; more"), std::string::npos);  // escaped title
  EXPECT_NE(svg.find("mean per-vertex error (cm)"), std::string::npos);
  EXPECT_NE(svg.find("test frame"), std::string::npos);
  EXPECT_NE(svg.find(">rbf, tuned</text>"), std::string::npos);  // legend
  EXPECT_NE(svg.find(">fear</text>"), std::string::npos);        // sequence label
  EXPECT_NE(svg.find("stroke=\"#d62728\""), std::string::npos);  // ours in red
  EXPECT_EQ(count(svg, "stroke-dasharray"), 1u);                 // one sequence boundary
  EXPECT_EQ(count(svg, "<text"), count(svg, "</text>"));
}

TEST_F(EvalOutputs, SvgOfASingleFrameAndOfZeroErrors) {
  const std::vector<FrameId> frames = {{"s", 0}};
  const std::string svg = frame_error_svg(frames, {"a", "b"}, {{0.0}, {0.0}}, "t");
  EXPECT_EQ(count(svg, "<polyline"), 2u);
  EXPECT_EQ(svg.find("nan"), std::string::npos);
  EXPECT_EQ(svg.find("inf"), std::string::npos);
}

TEST(EvalOutputsTicks, NiceStepsAreOneTwoOrFiveTimesAPowerOfTen) {
  EXPECT_DOUBLE_EQ(nice_tick_step(1.0, 5), 0.2);
  EXPECT_DOUBLE_EQ(nice_tick_step(0.37, 6), 0.1);
  EXPECT_DOUBLE_EQ(nice_tick_step(444, 8), 100);
  EXPECT_DOUBLE_EQ(nice_tick_step(30, 8), 5);
  EXPECT_DOUBLE_EQ(nice_tick_step(0, 8), 1);
}
