// Error paths of the OBJ reader, the ICT FaceKit loader and the CLI: every
// failure must be a facesr::Error naming the offending file (and line), and
// the CLI must exit non-zero without leaving partial output behind.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "mesh/obj_io.h"
#include "mesh/tetrahedralize.h"
#include "rig/ict_head.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

using fixtures::read_text;

fs::path make_temp_dir(const std::string& suite) {
  const fs::path d = fs::temp_directory_path() / ("facesr_err_" + std::to_string(::getpid()) + "_" + suite);
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  ASSERT_TRUE(out.good()) << p;
}

using fixtures::error_of;

// FaceKit layout constants (see engine/rig/ict_head.cpp).
constexpr int kSkinVerts = 14062;   // vertices 0..14061: face, head, mouth, eye sockets
constexpr int kTotalVerts = 21451;  // ... up to the lower teeth (21450)
constexpr int kGridW = 158, kGridH = 89;
static_assert(kGridW * kGridH == kSkinVerts, "skin grid must cover the skin range exactly");

// A fake FaceKit neutral: the skin range is a grid on a deep paraboloid bowl
// (a disk with a single boundary loop; the loader's fan cap over that loop
// stays above the bowl, so there are no self-intersections and the loader
// gets past the neck-cap step), the remaining vertices are loose points.
void write_fake_neutral(const fs::path& p) {
  std::string s;
  s.reserve(2 << 20);
  char buf[128];
  for (int j = 0; j < kGridH; ++j)
    for (int i = 0; i < kGridW; ++i) {
      const double x = 0.1 * (i - 0.5 * (kGridW - 1)), y = 0.1 * (j - 0.5 * (kGridH - 1)), z = x * x + y * y;
      std::snprintf(buf, sizeof buf, "v %.6f %.6f %.6f\n", x, y, z);
      s += buf;
    }
  for (int k = kSkinVerts; k < kTotalVerts; ++k) {
    std::snprintf(buf, sizeof buf, "v %.6f %.6f %.6f\n", 0.01 * (k % 100), 0.01 * (k / 100), -5.0);
    s += buf;
  }
  for (int j = 0; j + 1 < kGridH; ++j)
    for (int i = 0; i + 1 < kGridW; ++i) {
      const int a = j * kGridW + i + 1, b = a + 1, c = a + kGridW, d = c + 1;  // 1-based
      std::snprintf(buf, sizeof buf, "f %d %d %d\nf %d %d %d\n", a, b, d, a, d, c);
      s += buf;
    }
  write_text(p, s);
}

void write_fake_json(const fs::path& p) {
  nlohmann::json j;
  j["expressions"] = {"jawOpen"};
  std::vector<int> lm;
  for (int k = 0; k < 68; ++k) lm.push_back(k * 100);
  j["idx_to_landmark_verts"] = lm;
  write_text(p, j.dump());
}

std::string small_obj(int nverts, int nan_line = -1) {
  std::string s = "# blendshape\n";
  for (int k = 0; k < nverts; ++k) {
    if (k + 2 == nan_line)
      s += "v 1 nan 2\n";
    else
      s += "v " + std::to_string(k) + " 0 0\n";
  }
  return s;
}

// Builds the fake folder (neutral + json, no blendshapes yet) once per dir.
fs::path make_fake_ict(const fs::path& dir) {
  fs::create_directories(dir);
  write_fake_neutral(dir / "generic_neutral_mesh.obj");
  write_fake_json(dir / "vertex_indices.json");
  return dir;
}

// ---------------------------------------------------------------------------

class ObjErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = make_temp_dir("obj"); }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path ObjErrors::dir_;

TEST_F(ObjErrors, NanCoordinateNamesFileAndLine) {
  const fs::path p = dir_ / "nan.obj";
  write_text(p, "# c\nv 0 0 0\nv 1 nan 2\nv 1 1 1\n");
  for (bool faces : {true, false}) {
    const std::string msg = error_of([&] { faces ? (void)read_obj(p.string()) : (void)read_obj_vertices(p.string()); });
    EXPECT_NE(msg.find(p.string() + ":3:"), std::string::npos) << msg;
    EXPECT_NE(msg.find("NaN"), std::string::npos) << msg;
  }
  write_text(p, "v 0 0 0\nv inf 0 0\n");
  const std::string msg = error_of([&] { read_obj_vertices(p.string()); });
  EXPECT_NE(msg.find(p.string() + ":2:"), std::string::npos) << msg;
}

TEST_F(ObjErrors, MalformedVertexRowNamesFileAndLine) {
  const fs::path p = dir_ / "short.obj";
  write_text(p, "v 0 0 0\nv 0 1 0\nv 1 2\nv 1 1 1\n");
  const std::string msg = error_of([&] { read_obj(p.string()); });
  EXPECT_NE(msg.find(p.string() + ":3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("malformed"), std::string::npos) << msg;
  // Same row as the last line of a file without trailing newline.
  write_text(p, "v 0 0 0\nv 1 2");
  const std::string msg2 = error_of([&] { read_obj_vertices(p.string()); });
  EXPECT_NE(msg2.find(p.string() + ":2:"), std::string::npos) << msg2;
}

TEST_F(ObjErrors, FaceIndexOutOfRangeNamesFileAndLine) {
  const fs::path p = dir_ / "face.obj";
  write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 4\n");
  std::string msg = error_of([&] { read_obj(p.string()); });
  EXPECT_NE(msg.find(p.string() + ":5:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("out of range"), std::string::npos) << msg;
  write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n");  // OBJ indices are 1-based
  msg = error_of([&] { read_obj(p.string()); });
  EXPECT_NE(msg.find(p.string() + ":4:"), std::string::npos) << msg;
  write_text(p, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -1 -2 -4\n");  // relative index before the first vertex
  msg = error_of([&] { read_obj(p.string()); });
  EXPECT_NE(msg.find(p.string() + ":4:"), std::string::npos) << msg;
}

TEST_F(ObjErrors, MissingFileNamesPath) {
  const fs::path p = dir_ / "does_not_exist.obj";
  for (bool faces : {true, false}) {
    const std::string msg = error_of([&] { faces ? (void)read_obj(p.string()) : (void)read_obj_vertices(p.string()); });
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
  }
}

// ---------------------------------------------------------------------------

class RigErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = make_temp_dir("rig");
    ict_ = make_fake_ict(dir_ / "ict");
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  void TearDown() override {
    fs::remove(ict_ / "jawOpen.obj");
    write_fake_json(ict_ / "vertex_indices.json");
  }
  static fs::path dir_, ict_;
};
fs::path RigErrors::dir_, RigErrors::ict_;

TEST_F(RigErrors, MissingBlendshapeNamesFile) {
  const std::string msg = error_of([&] { load_ict_head(ict_.string(), false); });
  EXPECT_NE(msg.find((ict_ / "jawOpen.obj").string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing"), std::string::npos) << msg;
}

TEST_F(RigErrors, BlendshapeWithDifferentTopology) {
  const fs::path bs = ict_ / "jawOpen.obj";
  write_text(bs, small_obj(100));
  const std::string msg = error_of([&] { load_ict_head(ict_.string(), false); });
  EXPECT_NE(msg.find(bs.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("different topology"), std::string::npos) << msg;
  EXPECT_NE(msg.find("100"), std::string::npos) << msg;
  EXPECT_NE(msg.find(std::to_string(kTotalVerts)), std::string::npos) << msg;
}

TEST_F(RigErrors, MalformedJsonNamesFile) {
  const fs::path js = ict_ / "vertex_indices.json";
  write_text(js, "{\"expressions\": [\"jawOpen\", ");
  const std::string msg = error_of([&] { load_ict_head(ict_.string(), false); });
  EXPECT_NE(msg.find(js.string()), std::string::npos) << msg;
  EXPECT_NE(msg.find("JSON"), std::string::npos) << msg;
}

TEST_F(RigErrors, MissingFolderNamesIt) {
  const fs::path missing = dir_ / "no_such_folder";
  const std::string msg = error_of([&] { load_ict_head(missing.string(), false); });
  EXPECT_NE(msg.find(missing.string()), std::string::npos) << msg;
}

TEST_F(RigErrors, NanInBlendshapeNamesFileAndLine) {
  const fs::path bs = ict_ / "jawOpen.obj";
  write_text(bs, small_obj(50, /*nan_line=*/7));
  ASSERT_NE(read_text(bs).find("v 1 nan 2"), std::string::npos);
  const std::string msg = error_of([&] { load_ict_head(ict_.string(), false); });
  EXPECT_NE(msg.find(bs.string() + ":7:"), std::string::npos) << msg;
}

// ---------------------------------------------------------------------------

using fixtures::CliResult;

std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

class CliErrors : public ::testing::Test {
 protected:
  static void SetUpTestSuite() { dir_ = make_temp_dir("cli"); }
  static void TearDownTestSuite() { fs::remove_all(dir_); }

  static CliResult run(const std::string& args) { return fixtures::run_cli(args, dir_.string()); }

  // The coarse procedural rig (~4 s), built on first use and reused by the
  // suite's tests (lazily, so tests run one per process build it only when
  // they need it).
  static fs::path ok_rig() {
    const fs::path p = dir_ / "ok.rig";
    if (!fs::exists(p)) {
      const CliResult r = run("rig build --source procedural --preset coarse -q -o " + quote(p.string()));
      EXPECT_EQ(r.status, 0) << r.err;
    }
    return p;
  }

  static bool has_tmp_leftovers(const std::string& stem) {
    for (const auto& e : fs::directory_iterator(dir_))
      if (e.path().filename().string().rfind(stem + ".tmp", 0) == 0) return true;
    return false;
  }

  static fs::path dir_;
};
fs::path CliErrors::dir_;

TEST_F(CliErrors, BuildFromMissingFolder) {
  const fs::path out = dir_ / "x.rig";
  const CliResult r = run("rig build --source /nonexistent -q -o " + quote(out.string()));
  EXPECT_NE(r.status, 0);
  EXPECT_NE(r.err.find("facesr: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("/nonexistent"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(has_tmp_leftovers("x.rig"));
}

TEST_F(CliErrors, BuildWithBadBlendshape) {
  const fs::path ict = make_fake_ict(dir_ / "ict");
  const fs::path bs = ict / "jawOpen.obj";
  write_text(bs, small_obj(100));
  const fs::path out = dir_ / "bad.rig";
  const CliResult r = run("rig build --source " + quote(ict.string()) + " -q -o " + quote(out.string()));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("facesr: error:"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(bs.string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(has_tmp_leftovers("bad.rig"));
  fs::remove_all(ict);
}

TEST_F(CliErrors, InfoOnTruncatedRig) {
  const fs::path ok = ok_rig();
  ASSERT_TRUE(fs::exists(ok));
  const fs::path cut = dir_ / "cut.rig";
  fs::copy_file(ok, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(ok) / 2);
  const CliResult r = run("rig info " + quote(cut.string()));
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find("truncated"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(cut.string()), std::string::npos) << r.err;
}

TEST_F(CliErrors, InfoOnMissingFile) {
  const fs::path missing = dir_ / "missing.rig";
  const CliResult r = run("rig info " + quote(missing.string()) + " --json");
  EXPECT_EQ(r.status, 1) << r.err;
  EXPECT_NE(r.err.find(missing.string()), std::string::npos) << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST_F(CliErrors, InfoJsonOnValidRig) {
  const fs::path ok = ok_rig();
  const CliResult r = run("rig info " + quote(ok.string()) + " --json");
  ASSERT_EQ(r.status, 0) << r.err;
  nlohmann::json j;
  ASSERT_NO_THROW(j = nlohmann::json::parse(r.out)) << r.out;
  EXPECT_EQ(j.value("units", ""), "cm");
  ASSERT_TRUE(j.contains("hr_tets"));
  EXPECT_GT(j["hr_tets"].get<long>(), 0);
}

TEST_F(CliErrors, BuildHelpExitsZero) {
  const CliResult r = run("rig build --help");
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE((r.out + r.err).find("--source"), std::string::npos);
}

TEST_F(CliErrors, UnknownSubcommandFails) {
  CliResult r = run("frobnicate");
  EXPECT_NE(r.status, 0);
  EXPECT_FALSE(r.err.empty());
  r = run("rig frobnicate");
  EXPECT_NE(r.status, 0);
  EXPECT_FALSE(r.err.empty());
}

}  // namespace

namespace {
TriMesh unit_cube() {
  TriMesh m;
  m.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) m.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  m.F.resize(12, 3);
  m.F << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
         2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5;
  return m;
}
}  // namespace

// TetGen's refinement is bounded: a mesh that would need more added points
// than the bound is an error naming the bound, never an unbounded run (an
// identity head's sliver bone surface kept TetGen busy for over 15 minutes).
TEST(Tetrahedralize, RefinementBoundIsAnError) {
  TetgenOptions opt;
  opt.preserve_boundary = false;  // -Y keeps a cube's 12 triangles unsplit, and then nothing refines
  opt.max_volume = 0.00002;  // cm³: ~110,000 tets in a 1 cm cube, ~21,000 added points
  try {
    tetrahedralize(unit_cube(), {}, opt);
    FAIL() << "expected the Steiner bound to be reached";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("did not converge"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("10000"), std::string::npos) << e.what();
  }
  opt.max_steiner_per_input = 0;  // unbounded: the same mesh succeeds
  const TetMesh m = tetrahedralize(unit_cube(), {}, opt);
  EXPECT_GT(m.X.rows(), 10000);
  opt.max_volume = 0.01;  // a modest mesh stays well inside the default bound
  opt.max_steiner_per_input = 40;
  EXPECT_GT(tetrahedralize(unit_cube(), {}, opt).T.rows(), 100);
}
