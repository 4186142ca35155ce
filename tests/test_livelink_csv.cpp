// Live Link Face CSV import: column mapping (ARKit PascalCase to ICT and
// ARKit rig names), ignored and unknown columns, timecodes, resampling, every
// row error, load_performance's dispatch, and `facesr perf` on a CSV.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
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
  const Performance p = load_livelink_csv(path, kIct, 60, 30, &r);
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
  const Performance p = load_livelink_csv(secs, arkit, 60, 10, &r);
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
  const Performance q = load_livelink_csv(plain, arkit, 40, 20, &r);
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
  // Too few fields on line 3.
  std::string path = write("short.csv", head + good + "10:00:00:59.000,61,0.1,0.2\n");
  std::string msg = error_of([&] { load_livelink_csv(path, kIct); });
  EXPECT_HAS(msg, path + ": line 3: has 4 fields, the header has 19");
  // A word where a weight belongs, on line 4.
  std::string bad = good;
  bad.replace(bad.find("0.0,0.1,0.4"), 3, "abc");
  bad.replace(0, 15, "10:00:00:59.500");
  path = write("take.csv", head + good + "10:00:00:59.000,61,0.1,0.2,0.0,0.1,0.4,0.0,0.9,x,0,0,0,0,0,0,0,0,0\n" + bad);
  msg = error_of([&] { load_livelink_csv(path, kIct); });
  EXPECT_HAS(msg, path + ": line 4: column 'JawOpen': 'abc' is not a number");
  // Out of range, empty, NaN.
  for (const std::string v : {"1.2", "-0.05", "", "nan", "1e400"}) {
    std::string row = good;
    row.replace(row.find("0.0,0.1,0.4"), 3, v);
    msg = error_of([&] { load_livelink_csv(write("v.csv", head + row), kIct); });
    EXPECT_HAS(msg, "line 2: column 'JawOpen': '" + v + "'");
  }
  // Times that go back or stand still.
  for (const char* t : {"10:00:00:57.900", "10:00:00:58.000"}) {
    std::string row = good;
    row.replace(0, 15, t);
    path = write("time.csv", head + good + row);
    msg = error_of([&] { load_livelink_csv(path, kIct); });
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
  msg = error_of([&] { load_livelink_csv(write("fps.csv", head + good), kIct, 30); });
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
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, 0); }), "capture fps 0");
  EXPECT_HAS(error_of([&] { load_livelink_csv(path, kIct, 60, 5000); }), "output fps 5000");
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
