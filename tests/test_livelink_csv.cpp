// Live Link Face CSV import: column mapping (ARKit PascalCase to ICT and
// ARKit rig names), ignored and unknown columns, timecodes, resampling, every
// row error, load_performance's dispatch, and `facesr perf` on a CSV; the
// lenient mode's repairs (clamping, tracking-lost rows, repeated times, frame
// indices) with their warnings and strict mode's refusals; the real takes in
// ../shared/data/livelink when present.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "perf/livelink_csv.h"
#include "perf/performance.h"
#include "rig/rig_io.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;
using fixtures::error_of;

namespace {

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

// A few ICT-style shapes: sides as _L/_R, CheekPuff and BrowInnerUp split.
const std::vector<std::string> kIct = {"browInnerUp_L", "browInnerUp_R", "cheekPuff_L", "cheekPuff_R",
                                       "eyeBlink_L",    "eyeBlink_R",    "jawOpen",     "mouthClose",
                                       "mouthLeft",     "mouthSmile_L",  "mouthSmile_R"};

const char* kHeader =
    "Timecode,BlendShapeCount,EyeBlinkLeft,EyeBlinkRight,JawOpen,CheekPuff,BrowInnerUp,MouthLeft,TongueOut,"
    "FooBar,HeadYaw,HeadPitch,HeadRoll,LeftEyeYaw,LeftEyePitch,LeftEyeRoll,RightEyeYaw,RightEyePitch,RightEyeRoll";

// Rows at 60 fps frames 58, 59, 60.5 and 62 of a take, across a second
// boundary: relative times 0, 1/60, 2.5/60, 4/60 s. Head and eye angles and
// the unknown columns hold values that are no weights; they must be ignored.
const char* kRows =
    "10:00:00:58.000,61,1.005,0.2,0.0,0.1,0.4,0.0,0.9,x,0.3,-2.5,1,0,0,0,0,0,0\n"
    "10:00:00:59.000,61,0.5,0.2,0.3,0.1,0.4,0.0,0.9,x,0.3,-2.5,1,0,0,0,0,0,0\n"
    "10:00:01:00.500,61,0.5,0.2,0.6,0.4,0.4,0.0,0.9,x,0.3,-2.5,1,0,0,0,0,0,0\n"
    "10:00:01:02.000,61,-0.004,0.2,0.2,0.4,0.4,0.7,0.9,x,0.3,-2.5,1,0,0,0,0,0,0\n";

int index_of(const Performance& p, const std::string& name) {
  return int(std::find(p.names.begin(), p.names.end(), name) - p.names.begin());
}
float w(const Performance& p, int f, const std::string& name) { return p.frame(f)[index_of(p, name)]; }

LiveLinkOptions rates(double capture_fps, double out_fps) {
  LiveLinkOptions o;
  o.capture_fps = capture_fps;
  o.out_fps = out_fps;
  return o;
}
LiveLinkOptions strict() {
  LiveLinkOptions o;
  o.strict = true;
  return o;
}

class LiveLinkCsv : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_livelink_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static std::string write(const std::string& name, const std::string& text) {
    const fs::path p = dir_ / name;
    std::ofstream(p, std::ios::binary) << text;
    return p.string();
  }
  static fs::path dir_;
};
fs::path LiveLinkCsv::dir_;

}  // namespace

TEST_F(LiveLinkCsv, MapsColumnsAndResamplesTo30Fps) {
  const std::string path = write("take.csv", std::string(kHeader) + "\n" + kRows);
  LiveLinkReport r;
  const Performance p = load_livelink_csv(path, kIct, rates(60, 30), &r);
  EXPECT_EQ(p.name, "take");
  EXPECT_EQ(p.names, kIct);
  EXPECT_EQ(p.fps, 30);
  EXPECT_EQ(p.start_time, 0);
  EXPECT_FALSE(p.has_jaw);
  // Span 4/60 s at 30 fps: frames at 0, 2/60 and 4/60 s.
  ASSERT_EQ(p.frames(), 3);
  // Frame 1 (2/60 s) lies 2/3 of the way from row 2 (1/60) to row 3 (2.5/60).
  EXPECT_EQ(w(p, 0, "jawOpen"), 0.0f);
  EXPECT_FLOAT_EQ(w(p, 1, "jawOpen"), 0.3f + 2.0f / 3 * 0.3f);
  EXPECT_FLOAT_EQ(w(p, 2, "jawOpen"), 0.2f);
  EXPECT_FLOAT_EQ(w(p, 1, "cheekPuff_L"), 0.1f + 2.0f / 3 * 0.3f);
  EXPECT_FLOAT_EQ(w(p, 1, "cheekPuff_R"), w(p, 1, "cheekPuff_L"));  // one column drives both halves
  EXPECT_FLOAT_EQ(w(p, 2, "browInnerUp_R"), 0.4f);
  EXPECT_FLOAT_EQ(w(p, 2, "mouthLeft"), 0.7f);  // ARKit's sideless mouthLeft is not "mouth" + Left
  EXPECT_FLOAT_EQ(w(p, 1, "eyeBlink_R"), 0.2f);
  // Slight overshoots are clamped.
  EXPECT_EQ(w(p, 0, "eyeBlink_L"), 1.0f);
  EXPECT_EQ(w(p, 2, "eyeBlink_L"), 0.0f);
  for (int f = 0; f < 3; ++f) EXPECT_EQ(w(p, f, "mouthSmile_L"), 0.0f);

  EXPECT_TRUE(r.has_timecode);
  EXPECT_EQ(r.rows, 4);
  EXPECT_NEAR(r.first_time_s, 36000 + 58.0 / 60, 1e-9);
  EXPECT_NEAR(r.last_time_s - r.first_time_s, 4.0 / 60, 1e-9);
  ASSERT_EQ(r.mapped.size(), 6u);
  EXPECT_EQ(r.mapped[0].column, "EyeBlinkLeft");
  EXPECT_EQ(r.mapped[0].shapes, std::vector<std::string>{"eyeBlink_L"});
  EXPECT_EQ(r.mapped[3].column, "CheekPuff");
  EXPECT_EQ(r.mapped[3].shapes, (std::vector<std::string>{"cheekPuff_L", "cheekPuff_R"}));
  EXPECT_EQ(r.unknown, (std::vector<std::string>{"TongueOut", "FooBar"}));
  ASSERT_EQ(r.ignored.size(), 10u);  // BlendShapeCount and nine head/eye angles
  EXPECT_EQ(r.ignored[0].column, "BlendShapeCount");
  EXPECT_EQ(r.ignored[1].column, "HeadYaw");
  EXPECT_HAS(r.ignored[1].reason, "head rotation");
  EXPECT_EQ(r.ignored[9].column, "RightEyeRoll");
  EXPECT_HAS(r.ignored[9].reason, "eye rotation");
  EXPECT_EQ(r.shapes_without_column, (std::vector<std::string>{"mouthClose", "mouthSmile_L", "mouthSmile_R"}));
  const std::string summary = livelink_report_summary(r);
  EXPECT_HAS(summary, "6 columns mapped");
  EXPECT_HAS(summary, "TongueOut, FooBar");
  const nlohmann::json j = livelink_report_json(r);
  EXPECT_EQ(j["unknown_columns"], 2);
  EXPECT_EQ(j["ignored_columns"], 10);
  EXPECT_EQ(j["mapped"]["CheekPuff"].size(), 2u);
}

TEST_F(LiveLinkCsv, ArkitStyleRigNamesSecondsAndNoTimecode) {
  // An ARKit-named rig takes the columns with the first letter lowered.
  const std::vector<std::string> arkit = {"eyeBlinkLeft", "jawOpen", "cheekPuff"};
  // Plain seconds, CRLF line ends and a trailing blank line; output at 10 fps.
  const std::string secs = write("secs.csv",
                                 "Timecode,EyeBlinkLeft,JawOpen,CheekPuff\r\n"
                                 "1.0,0,0,0.5\r\n1.2,1,0.4,0.5\r\n1.3,0,0.2,0.5\r\n\r\n");
  LiveLinkReport r;
  const Performance p = load_livelink_csv(secs, arkit, rates(60, 10), &r);
  ASSERT_EQ(p.frames(), 4);  // 0, 0.1, 0.2, 0.3 s after the first row
  EXPECT_FLOAT_EQ(p.frame(1)[0], 0.5f);
  EXPECT_FLOAT_EQ(p.frame(1)[1], 0.2f);
  EXPECT_FLOAT_EQ(p.frame(2)[1], 0.4f);
  EXPECT_FLOAT_EQ(p.frame(3)[1], 0.2f);
  EXPECT_FLOAT_EQ(p.frame(3)[2], 0.5f);
  EXPECT_EQ(r.mapped.size(), 3u);
  EXPECT_TRUE(r.shapes_without_column.empty());
  // Without a Timecode column rows are 1/capture_fps apart.
  const std::string plain = write("plain.csv", "JawOpen\n0\n0.2\n0.4\n0.6\n0.8\n");
  const Performance q = load_livelink_csv(plain, arkit, rates(40, 20), &r);
  EXPECT_FALSE(r.has_timecode);
  ASSERT_EQ(q.frames(), 3);  // 5 rows 1/40 s apart span 0.1 s: 3 frames at 20 fps
  EXPECT_FLOAT_EQ(q.frame(1)[1], 0.4f);
  EXPECT_FLOAT_EQ(q.frame(2)[1], 0.8f);
  // One row: one frame.
  EXPECT_EQ(load_livelink_csv(write("one.csv", "Timecode,JawOpen\n00:00:01:00.0,0.3\n"), arkit).frames(), 1);
}

TEST_F(LiveLinkCsv, RowErrorsNameFileLineAndColumn) {
  const std::string head = std::string(kHeader) + "\n";
  const std::string good = "10:00:00:58.000,61,0.1,0.2,0.0,0.1,0.4,0.0,0.9,x,0.3,-2.5,1,0,0,0,0,0,0\n";
  // Too few fields on line 3 (tracking lost): refused in strict mode only.
  std::string path = write("short.csv", head + good + "10:00:00:59.000,61,0.1,0.2\n");
  std::string msg = error_of([&] { load_livelink_csv(path, kIct, strict()); });
  EXPECT_HAS(msg, path + ": line 3: has 4 fields, the header has 19");
  EXPECT_HAS(msg, "tracking lost?");
  // Too many: refused in both modes.
  path = write("long.csv", head + good + good.substr(0, good.size() - 1) + ",7\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), path + ": line 3: has 20 fields, the header has 19");
  // A word where a weight belongs, on line 4.
  std::string bad = good;
  bad.replace(bad.find("0.0,0.1,0.4"), 3, "abc");
  bad.replace(0, 15, "10:00:00:59.500");
  path = write("take.csv", head + good + "10:00:00:59.000,61,0.1,0.2,0.0,0.1,0.4,0.0,0.9,x,0,0,0,0,0,0,0,0,0\n" + bad);
  msg = error_of([&] { load_livelink_csv(path, kIct); });
  EXPECT_HAS(msg, path + ": line 4: column 'JawOpen': 'abc' is not a number");
  // Beyond the tolerance, empty, NaN, inf.
  for (const std::string v : {"1.2", "-0.15", "", "nan", "1e400", "inf"}) {
    std::string row = good;
    row.replace(row.find("0.0,0.1,0.4"), 3, v);
    msg = error_of([&] { load_livelink_csv(write("v.csv", head + row), kIct); });
    EXPECT_HAS(msg, "line 2: column 'JawOpen': '" + v + "'");
  }
  // Times that go back (both modes) or stand still (strict; lenient drops the repeat).
  for (const char* t : {"10:00:00:57.900", "10:00:00:58.000"}) {
    std::string row = good;
    row.replace(0, 15, t);
    path = write("time.csv", head + good + row);
    msg = error_of([&] { load_livelink_csv(path, kIct, strict()); });
    EXPECT_HAS(msg, path + ": line 3: time");
    EXPECT_HAS(msg, "not after line 2's");
    EXPECT_HAS(msg, "times must increase");
  }
  // Broken timecodes, and a frame beyond the capture rate.
  for (const char* t : {"10:00:58.000", "10:00:00:xx", "ten"}) {
    std::string row = good;
    row.replace(0, 15, t);
    msg = error_of([&] { load_livelink_csv(write("tc.csv", head + row), kIct); });
    EXPECT_HAS(msg, "line 2: column 'Timecode'");
  }
  msg = error_of([&] { load_livelink_csv(write("fps.csv", head + good), kIct, rates(30, 30)); });
  EXPECT_HAS(msg, "frame 58");
  EXPECT_HAS(msg, "capture rate 30 fps");
}

TEST_F(LiveLinkCsv, FileErrors) {
  std::string path = write("empty.csv", "");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), path + ": is empty");
  path = write("blank.csv", "\n  \n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), path + ": is empty");
  path = write("header.csv", std::string(kHeader) + "\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), path + ": has a header but no data rows");
  path = write("dup.csv", "Timecode,JawOpen,JawOpen\n0,0,0\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), "'JawOpen' repeats column 2");
  path = write("twice.csv", "Timecode,CheekPuff,CheekPuffLeft\n0,0,0\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }), "would both drive rig shape 'cheekPuff_L'");
  const std::string missing = (dir_ / "nope.csv").string();
  EXPECT_HAS(error_of([&] { load_livelink_csv(missing, kIct); }), missing + ": cannot open");
  path = write("ok.csv", "JawOpen\n0.5\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, rates(0, 30)); }), "capture fps 0");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, rates(60, 5000)); }), "output fps 5000");
  LiveLinkOptions o;
  o.weight_tolerance = 0.9;
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, o); }), "weight tolerance 0.9 is not in [1, 2]");
  // Every row tracking-lost: nothing to play.
  path = write("lost.csv", "Timecode,BlendShapeCount,JawOpen\n0.0,0\n0.1,0\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct); }),
             path + ": no tracked rows: all 2 data rows have fewer fields than the header");
}

TEST_F(LiveLinkCsv, LoadPerformanceDispatchesOnExtension) {
  const std::string csv = write("take.CSV", std::string(kHeader) + "\n" + kRows);
  LiveLinkReport r;
  const Performance a = load_performance(csv, kIct, &r);
  EXPECT_EQ(a.frames(), 3);
  EXPECT_EQ(r.rows, 4);
  EXPECT_EQ(a.weights, load_livelink_csv(csv, kIct).weights);  // defaults: 60 fps capture, 30 fps out
  const std::string json = (dir_ / "take.json").string();
  save_performance_json(a, json);
  LiveLinkReport untouched;
  untouched.rows = -7;
  const Performance b = load_performance(json, kIct, &untouched);
  EXPECT_EQ(b.weights, a.weights);
  EXPECT_EQ(untouched.rows, -7);  // only a CSV fills the report
  const std::string txt = write("take.txt", "JawOpen\n0\n");
  const std::string msg = error_of([&] { load_performance(txt, kIct); });
  EXPECT_HAS(msg, txt + ": unknown performance file type '.txt'");
  EXPECT_HAS(error_of([&] { load_performance((dir_ / "none.json").string(), kIct); }), "cannot open");
}

// `facesr perf show|write --performance take.csv` on the procedural rig.
TEST_F(LiveLinkCsv, PerfCliReadsCsv) {
  const std::string rig = (dir_ / "procedural.rig").string();
  save_rig(fixtures::procedural_rig(), rig);
  const std::string csv = write("cli.csv", std::string(kHeader) + "\n" + kRows);
  using fixtures::shell_quote;
  const std::string scratch = dir_.string();
  fixtures::CliResult r =
      fixtures::run_cli("perf show --rig " + shell_quote(rig) + " --performance " + shell_quote(csv) + " --json",
                        scratch);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["frames"], 3);
  ASSERT_TRUE(j.contains("csv")) << r.out;
  // The procedural head has no eye blinks or mouthLeft: those columns are unknown to it.
  EXPECT_EQ(j["csv"]["mapped_columns"], 3);  // JawOpen, CheekPuff, BrowInnerUp
  EXPECT_EQ(j["csv"]["ignored_columns"], 10);
  const auto unknown = j["csv"]["unknown"].get<std::vector<std::string>>();
  EXPECT_NE(std::find(unknown.begin(), unknown.end(), "TongueOut"), unknown.end());
  EXPECT_NE(std::find(unknown.begin(), unknown.end(), "EyeBlinkLeft"), unknown.end());
  EXPECT_HAS(r.err, "3 columns mapped");
  EXPECT_HAS(r.err, "TongueOut");

  const std::string out = (dir_ / "cli.json").string();
  r = fixtures::run_cli("perf write --rig " + shell_quote(rig) + " --performance " + shell_quote(csv) + " -o " +
                            shell_quote(out) + " --json",
                        scratch);
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(nlohmann::json::parse(r.out).contains("csv"));
  const Performance p = load_performance_json(out, fixtures::procedural_rig().blendshape_names);
  EXPECT_EQ(p.frames(), 3);
  EXPECT_FLOAT_EQ(p.frame(1)[index_of(p, "jawOpen")], 0.5f);

  const std::string txt = write("take.txt", "x");
  r = fixtures::run_cli("perf show --rig " + shell_quote(rig) + " --performance " + shell_quote(txt), scratch);
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, txt);
  r = fixtures::run_cli("perf write --rig " + shell_quote(rig) + " -o " + shell_quote(out), scratch);
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, "exactly one of --performance FILE and --builtin NAME");
}

// Lenient mode: weights within the tolerance are clamped, counted and warned about once.
TEST_F(LiveLinkCsv, ClampsSmallOvershootsWithAWarning) {
  const std::string path = write("clamp.csv",
                                 "Timecode,JawOpen,EyeBlinkLeft\n"
                                 "0.0,0.5,0.2\n"
                                 "0.1,1.04,-0.08\n"  // line 3: both clamped
                                 "0.2,0.3,1.1\n");   // line 4: the tolerance itself is still clamped
  LiveLinkReport r;
  const Performance p = load_livelink_csv(path, kIct, rates(60, 10), &r);
  ASSERT_EQ(p.frames(), 3);
  EXPECT_EQ(w(p, 1, "jawOpen"), 1.0f);
  EXPECT_EQ(w(p, 1, "eyeBlink_L"), 0.0f);
  EXPECT_EQ(w(p, 2, "eyeBlink_L"), 1.0f);
  EXPECT_FLOAT_EQ(w(p, 2, "jawOpen"), 0.3f);
  EXPECT_EQ(r.clamped_values, 3);
  EXPECT_EQ(r.first_clamped_line, 3);
  EXPECT_EQ(r.first_clamped_column, "JawOpen");
  EXPECT_DOUBLE_EQ(r.first_clamped_value, 1.04);
  EXPECT_DOUBLE_EQ(r.farthest_clamped_value, 1.1);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0], "3 weights outside [0, 1] clamped (first at line 3, column 'JawOpen': 1.04; farthest 1.1)");
  const nlohmann::json j = livelink_report_json(r);
  EXPECT_EQ(j["clamped_values"], 3);
  EXPECT_EQ(j["first_clamped"]["line"], 3);
  EXPECT_EQ(j["first_clamped"]["column"], "JawOpen");
  EXPECT_EQ(j["warnings"].size(), 1u);
  EXPECT_EQ(j["timecode_mode"], "seconds");
  EXPECT_EQ(j["strict"], false);
  EXPECT_EQ(j["tracking_lost_rows"], 0);
  // A clean take warns about nothing.
  load_livelink_csv(write("clean.csv", "Timecode,JawOpen\n0,0\n0.1,1\n"), kIct, rates(60, 10), &r);
  EXPECT_EQ(r.clamped_values, 0);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_FALSE(livelink_report_json(r).contains("first_clamped"));
}

TEST_F(LiveLinkCsv, RefusesWeightsBeyondTheTolerance) {
  for (const std::string v : {"1.11", "-0.11", "3"}) {
    const std::string path = write("far.csv", "Timecode,JawOpen\n0.0,0.5\n0.1," + v + "\n");
    const std::string msg = error_of([&] { load_livelink_csv(path, kIct); });
    EXPECT_HAS(msg, path + ": line 3: column 'JawOpen': '" + v + "' is outside the weight range [0, 1]");
    EXPECT_HAS(msg, "only weights in [-0.1, 1.1] are clamped");
  }
  // A wider tolerance takes it.
  LiveLinkOptions wide;
  wide.weight_tolerance = 1.2;
  LiveLinkReport r;
  const std::string path = write("far.csv", "Timecode,JawOpen\n0.0,0.5\n0.1,-0.1\n0.2,1.15\n");
  const Performance p = load_livelink_csv(path, kIct, wide, &r);
  EXPECT_EQ(r.clamped_values, 2);
  EXPECT_DOUBLE_EQ(r.first_clamped_value, -0.1);
  EXPECT_DOUBLE_EQ(r.farthest_clamped_value, 1.15);
  EXPECT_EQ(p.frame(p.frames() - 1)[index_of(p, "jawOpen")], 1.0f);
}

// Strict mode refuses, by name, each thing lenient mode repairs.
TEST_F(LiveLinkCsv, StrictRefusesWhatLenientRepairs) {
  std::string path = write("s.csv", "Timecode,JawOpen\n0.0,0.5\n0.1,1.02\n");
  std::string msg = error_of([&] { load_livelink_csv(path, kIct, strict()); });
  EXPECT_HAS(msg, path + ": line 3: column 'JawOpen': '1.02' is outside the weight range [0, 1]");
  EXPECT_HAS(msg, "strict");
  path = write("s.csv", "Timecode,JawOpen\n0.0,-0.001\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, strict()); }), "line 2: column 'JawOpen': '-0.001'");
  // [0, 1] itself is fine.
  LiveLinkReport r;
  load_livelink_csv(write("s.csv", "Timecode,JawOpen\n0.0,0\n0.1,1\n"), kIct, strict(), &r);
  EXPECT_TRUE(r.strict);
  EXPECT_TRUE(r.warnings.empty());
  EXPECT_EQ(livelink_report_json(r)["strict"], true);
  // Tracking lost: the first such line is named.
  path = write("s.csv", "Timecode,BlendShapeCount,JawOpen\n0.0,61,0.5\n0.1,0\n0.2,0\n0.3,61,0.5\n");
  msg = error_of([&] { load_livelink_csv(path, kIct, strict()); });
  EXPECT_HAS(msg, path + ": line 3: has 2 fields, the header has 3");
  // A repeated time.
  path = write("s.csv", "Timecode,JawOpen\n0.0,0.5\n0.1,0.5\n0.1,0.6\n");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, strict()); }), path + ": line 4: time 0.1 s is not after");
}

// Tracking-lost rows: interpolated in time between the tracked rows around
// them, the nearest tracked row held at either end; the take keeps its length.
TEST_F(LiveLinkCsv, InterpolatesTrackingLostRows) {
  const std::string path = write("lost.csv",
                                 "Timecode,BlendShapeCount,JawOpen,CheekPuff\n"
                                 "0.0,0\n"             // line 2: lost at the start
                                 "0.1,61,0.2,0.5\n"    // line 3
                                 "0.2,0\n0.3,0\n0.4,0\n"  // lines 4-6
                                 "0.5,61,0.6,0.1\n"    // line 7
                                 "0.6,61,0.4,0.1\n"    // line 8
                                 "0.7,0\n");           // line 9: lost at the end
  LiveLinkReport r;
  const Performance p = load_livelink_csv(path, kIct, rates(60, 10), &r);
  ASSERT_EQ(p.frames(), 8);
  EXPECT_NEAR(p.duration(), 0.7, 1e-9);
  const float jaw[8] = {0.2f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f, 0.4f, 0.4f};
  for (int f = 0; f < 8; ++f) EXPECT_NEAR(w(p, f, "jawOpen"), jaw[f], 1e-6) << "frame " << f;
  EXPECT_NEAR(w(p, 3, "cheekPuff_R"), 0.3f, 1e-6);  // halfway from 0.5 to 0.1
  EXPECT_EQ(r.rows, 8);
  EXPECT_EQ(r.tracking_lost_rows, 5);
  EXPECT_EQ(r.tracking_lost_lines, (LiveLinkReport::LineRanges{{2, 2}, {4, 6}, {9, 9}}));
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_EQ(r.warnings[0],
            "5 tracking-lost rows (lines 2, 4-6, 9) interpolated between the tracked rows around them; those at the "
            "start and end of the take hold the nearest tracked row");
  const nlohmann::json j = livelink_report_json(r);
  EXPECT_EQ(j["tracking_lost_rows"], 5);
  EXPECT_EQ(j["tracking_lost_lines"][1], nlohmann::json::array({4, 6}));

  // Many runs: the warning lists six and counts the rest.
  std::string text = "Timecode,BlendShapeCount,JawOpen\n";
  for (int i = 0; i < 9; ++i)
    text += std::to_string(2 * i) + ".5,61,0.5\n" + std::to_string(2 * i + 1) + ".5,0\n";
  load_livelink_csv(write("runs.csv", text), kIct, LiveLinkOptions(), &r);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_HAS(r.warnings[0], "9 tracking-lost rows (lines 3, 5, 7, 9, 11, 13 and 3 more runs)");
  EXPECT_HAS(r.warnings[0], "those at the end of the take hold the last tracked row");
}

// Repeated times: the first tracked row of the instant is kept, with a warning.
TEST_F(LiveLinkCsv, DropsRepeatedTimes) {
  const std::string path = write("rep.csv",
                                 "Timecode,BlendShapeCount,JawOpen\n"
                                 "0.0,61,0.1\n"
                                 "0.1,61,0.2\n"
                                 "0.1,61,0.9\n"   // line 4: a repeat, dropped
                                 "0.2,0\n"        // line 5: lost ...
                                 "0.2,61,0.4\n"   // line 6: ... and replaced by a tracked row of its time
                                 "0.3,61,0.5\n");
  LiveLinkReport r;
  const Performance p = load_livelink_csv(path, kIct, rates(60, 10), &r);
  ASSERT_EQ(p.frames(), 4);
  EXPECT_FLOAT_EQ(w(p, 1, "jawOpen"), 0.2f);
  EXPECT_FLOAT_EQ(w(p, 2, "jawOpen"), 0.4f);
  EXPECT_EQ(r.repeated_time_rows, 1);
  EXPECT_EQ(r.repeated_time_lines, (LiveLinkReport::LineRanges{{4, 4}}));
  ASSERT_EQ(r.warnings.size(), 2u);
  EXPECT_EQ(r.warnings[1], "1 row repeating the previous row's time (line 4) dropped");
  EXPECT_EQ(livelink_report_json(r)["repeated_time_rows"], 1);
}

// A Timecode column counting frames is read at capture_fps, not as seconds.
TEST_F(LiveLinkCsv, DetectsFrameIndexTimecodes) {
  std::string text = "Timecode,JawOpen\n";
  for (int i = 0; i <= 120; ++i) text += std::to_string(i) + "," + std::to_string(i / 120.0) + "\n";
  const std::string path = write("frames.csv", text);
  LiveLinkReport r;
  const Performance p = load_livelink_csv(path, kIct, LiveLinkOptions(), &r);
  EXPECT_EQ(r.timecode, LiveLinkTimecode::FrameIndex);
  EXPECT_NEAR(p.duration(), 2.0, 1e-9);  // 120 frames at 60 fps, not 120 s
  ASSERT_EQ(p.frames(), 61);
  EXPECT_NEAR(w(p, 30, "jawOpen"), 0.5f, 1e-6);
  EXPECT_NEAR(r.last_time_s, 2.0, 1e-9);
  ASSERT_EQ(r.warnings.size(), 1u);
  EXPECT_HAS(r.warnings[0], "counts frames");
  EXPECT_HAS(r.warnings[0], "read as frames at 60 fps");
  EXPECT_EQ(livelink_report_json(r)["timecode_mode"], "frame_index");
  const std::string msg = error_of([&] { load_livelink_csv(path, kIct, strict()); });
  EXPECT_HAS(msg, path + ": column 'Timecode' holds whole numbers stepping by 1 (lines 2-122)");
  EXPECT_HAS(msg, "frame indices, not seconds");
  // A skipped index (a dropped frame) is a gap, not a reason to read seconds.
  const Performance q = load_livelink_csv(write("gap.csv", "Timecode,JawOpen\n10,0\n11,0\n12,0\n14,1\n"), kIct,
                                          rates(40, 20), &r);
  EXPECT_EQ(r.timecode, LiveLinkTimecode::FrameIndex);
  EXPECT_NEAR(q.duration(), 0.1, 1e-9);  // 4 frames at 40 fps
  // Seconds stay seconds: fractions, whole steps of 2, or only two rows.
  for (const char* rows : {"0,0\n0.5,0\n1,0\n1.5,0\n", "0,0\n2,0\n4,0\n", "0,0\n1,0\n"}) {
    load_livelink_csv(write("secs.csv", std::string("Timecode,JawOpen\n") + rows), kIct, LiveLinkOptions(), &r);
    EXPECT_EQ(r.timecode, LiveLinkTimecode::Seconds) << rows;
    EXPECT_TRUE(r.warnings.empty()) << rows;
  }
  load_livelink_csv(write("clock.csv", "Timecode,JawOpen\n00:00:01:00.0,0\n00:00:01:01.0,0\n00:00:01:02.0,0\n"),
                    kIct, LiveLinkOptions(), &r);
  EXPECT_EQ(r.timecode, LiveLinkTimecode::Clock);
}

// `facesr perf show` prints the warnings once on stderr, puts them in the
// JSON, and refuses with --strict; play and dataset take --strict too.
TEST_F(LiveLinkCsv, PerfCliWarnsOnceAndStrictRefuses) {
  const std::string rig = (dir_ / "procedural.rig").string();
  save_rig(fixtures::procedural_rig(), rig);
  const std::string csv = write("warn.csv", "Timecode,BlendShapeCount,JawOpen,CheekPuff\n"
                                            "0.0,61,0.5,0.2\n0.1,61,1.04,0.2\n0.2,0\n0.3,61,0.5,0.2\n");
  using fixtures::shell_quote;
  const std::string scratch = dir_.string();
  const std::string args = "perf show --rig " + shell_quote(rig) + " --performance " + shell_quote(csv) + " --json";
  fixtures::CliResult r = fixtures::run_cli(args, scratch);
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["csv"]["clamped_values"], 1);
  EXPECT_EQ(j["csv"]["tracking_lost_rows"], 1);
  EXPECT_EQ(j["csv"]["warnings"].size(), 2u);
  EXPECT_HAS(r.err, csv + ": warning: 1 weight outside [0, 1] clamped (first at line 3, column 'JawOpen'");
  EXPECT_HAS(r.err, csv + ": warning: 1 tracking-lost row (line 4) interpolated");
  size_t warnings = 0;
  for (size_t at = r.err.find("warning:"); at != std::string::npos; at = r.err.find("warning:", at + 1)) ++warnings;
  EXPECT_EQ(warnings, 2u) << r.err;
  r = fixtures::run_cli(args + " --strict", scratch);
  EXPECT_NE(r.status, 0);
  EXPECT_HAS(r.err, csv + ": line 3: column 'JawOpen': '1.04' is outside the weight range [0, 1]");
  for (const char* cmd : {"play --help", "bench runtime --help", "dataset --help", "perf write --help"}) {
    r = fixtures::run_cli(cmd, scratch);
    EXPECT_HAS(r.out + r.err, "--strict") << cmd;
  }
}

namespace {

// $FACESR_LIVELINK_DIR or ../shared/data/livelink, as fixtures::ict_dir finds the ICT head.
std::string livelink_dir() {
  const char* env = std::getenv("FACESR_LIVELINK_DIR");
  return env ? env : std::string(FACESR_TEST_SOURCE_DIR) + "/../shared/data/livelink";
}

// An ARKit-named rig for a take: every blendshape column of its header, first
// letter lowered, so every weight in the file is read and checked.
std::vector<std::string> arkit_names_of(const std::string& path) {
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  std::vector<std::string> names;
  std::stringstream fields(header);
  for (std::string c; std::getline(fields, c, ',');) {
    if (!c.empty() && c.back() == '\r') c.pop_back();
    if (c == "Timecode" || c == "BlendShapeCount" || c.rfind("Head", 0) == 0 || c.rfind("LeftEye", 0) == 0 ||
        c.rfind("RightEye", 0) == 0)
      continue;
    c[0] = char(std::tolower(static_cast<unsigned char>(c[0])));
    names.push_back(c);
  }
  return names;
}

}  // namespace

// The four real takes (see ../shared/data/livelink/README.md): all play in
// lenient mode for about their timecode span; the two flawed ones are
// refused by strict mode at the first flaw.
TEST_F(LiveLinkCsv, RealTakesFromSharedData) {
  const std::string dir = livelink_dir();
  if (!fs::is_directory(dir)) GTEST_SKIP() << "no Live Link takes at " << dir << " (set FACESR_LIVELINK_DIR)";
  struct Take {
    const char* file;
    double duration_s;
    int clamped, lost;
  };
  const Take takes[] = {{"MySlate_3_Jason_Millers_iPhone.csv", 5.45, 0, 0},
                        {"alexdjulin_S07-001.csv", 67.6, 0, 0},
                        {"alexdjulin_alex_rom_4.csv", 127.0, 91, 0},
                        {"alexdjulin_S88-001.csv", 64.7, 0, 277}};
  for (const Take& t : takes) {
    const std::string path = dir + "/" + t.file;
    ASSERT_TRUE(fs::exists(path)) << path;
    const std::vector<std::string> names = arkit_names_of(path);
    ASSERT_GE(names.size(), 52u) << path;
    LiveLinkReport r;
    const Performance p = load_livelink_csv(path, names, LiveLinkOptions(), &r);
    EXPECT_EQ(r.mapped.size(), names.size()) << path;
    EXPECT_EQ(r.timecode, LiveLinkTimecode::Clock) << path;
    EXPECT_NEAR(p.duration(), r.last_time_s - r.first_time_s, 1.0 / 30) << path;
    EXPECT_NEAR(p.duration(), t.duration_s, 0.05) << path;
    EXPECT_EQ(r.clamped_values, t.clamped) << path;
    EXPECT_EQ(r.tracking_lost_rows, t.lost) << path;
    EXPECT_EQ(r.repeated_time_rows, 0) << path;
    EXPECT_EQ(r.warnings.size(), size_t(t.clamped > 0) + size_t(t.lost > 0)) << path;
    for (float v : p.weights) ASSERT_TRUE(v >= 0 && v <= 1) << path;
  }
  const std::string rom = dir + "/alexdjulin_alex_rom_4.csv", s88 = dir + "/alexdjulin_S88-001.csv";
  LiveLinkReport r;
  load_livelink_csv(rom, arkit_names_of(rom), LiveLinkOptions(), &r);
  EXPECT_EQ(r.first_clamped_line, 538);
  EXPECT_EQ(r.first_clamped_column, "EyeLookInRight");
  EXPECT_HAS(r.warnings[0], "91 weights outside [0, 1] clamped (first at line 538, column 'EyeLookInRight'");
  load_livelink_csv(s88, arkit_names_of(s88), LiveLinkOptions(), &r);
  EXPECT_EQ(r.tracking_lost_lines, (LiveLinkReport::LineRanges{{384, 512}, {1713, 1835}, {1841, 1865}}));
  EXPECT_HAS(r.warnings[0], "277 tracking-lost rows (lines 384-512, 1713-1835, 1841-1865) interpolated");

  EXPECT_HAS(error_of([&] { load_livelink_csv(rom, arkit_names_of(rom), strict()); }),
             rom + ": line 538: column 'EyeLookInRight'");
  EXPECT_HAS(error_of([&] { load_livelink_csv(s88, arkit_names_of(s88), strict()); }),
             s88 + ": line 384: has 2 fields, the header has 63");
}

// Found by fuzzing: one wrong digit in a timecode's hours made four rows span
// ten hours, and the reader interpolated 1.1 million frames. The length is
// bounded (perf_limits.h: two hours at 30 fps), so such a take is refused at
// once, naming the span.
TEST_F(LiveLinkCsv, ATimecodeTypoThatSpansHoursIsRefused) {
  const std::string path = write("typo.csv",
                                 "Timecode,JawOpen\n"
                                 "09:35:05:27.466,0.1\n"
                                 "19:35:05:29.466,0.2\n");
  for (const auto& o : {LiveLinkOptions(), strict()}) {
    const std::string msg = error_of([&] { load_livelink_csv(path, kIct, o); });
    EXPECT_HAS(msg, "typo.csv: the take spans 36000");
    EXPECT_HAS(msg, "216000 frames");
  }
  // Just under two hours still loads.
  const std::string ok = write("long.csv", "Timecode,JawOpen\n0,0.1\n7199,0.2\n");
  EXPECT_EQ(load_livelink_csv(ok, kIct).frames(), 7199 * 30 + 1);
}
