#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>

#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "rig/rig_io.h"
#include "rig/rig_summary.h"
#include "tiny_files.h"

namespace fs = std::filesystem;
using namespace facesr;

namespace {

// Every field set and mutually consistent (the fuzzers' seed rig).
Rig make_rig() { return tiny::rig(); }

std::vector<uint8_t> read_bytes(const fs::path& p) { return read_file_bytes(p.string()); }

void write_bytes(const fs::path& p, const std::vector<uint8_t>& b) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(b.data()), std::streamsize(b.size()));
}

// Re-seals a patched file so that only the intended defect remains.
void reseal(std::vector<uint8_t>& b) {
  uint64_t payload_size;
  std::memcpy(&payload_size, b.data() + 16, 8);
  const uint64_t sum = fnv1a64(b.data() + 24, payload_size);
  std::memcpy(b.data() + 24 + payload_size, &sum, 8);
}

// Runs f, expecting an Error whose message contains every one of `parts`.
template <class F>
void expect_error(F f, std::initializer_list<std::string> parts) {
  try {
    f();
    ADD_FAILURE() << "no Error thrown";
  } catch (const Error& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos)
          << "message \"" << e.what() << "\" lacks \"" << p << "\"";
  }
}

class RigIo : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("facesr_rig_io_" + std::to_string(std::random_device{}()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  fs::path dir_;
};

}  // namespace

TEST_F(RigIo, RoundTripIsBitExact) {
  const Rig a = make_rig();
  save_rig(a, path("a.rig"));
  const Rig b = load_rig(path("a.rig"));
  save_rig(b, path("b.rig"));
  EXPECT_EQ(read_bytes(path("a.rig")), read_bytes(path("b.rig")));

  EXPECT_EQ(b.name, a.name);
  EXPECT_EQ(b.units, "cm");
  EXPECT_EQ(b.source, a.source);
  EXPECT_EQ(b.build_seconds, a.build_seconds);
  EXPECT_EQ(b.surface, a.surface);
  EXPECT_EQ(b.surface_tris, a.surface_tris);
  EXPECT_EQ(b.surface_source_vertex, a.surface_source_vertex);
  EXPECT_EQ(b.blendshape_names, a.blendshape_names);
  EXPECT_EQ(b.blendshape_deltas, a.blendshape_deltas);
  EXPECT_EQ(b.landmark_names, a.landmark_names);
  EXPECT_EQ(b.landmark_vertex, a.landmark_vertex);
  EXPECT_EQ(b.jaw.pivot, a.jaw.pivot);
  EXPECT_EQ(b.jaw.axis, a.jaw.axis);
  EXPECT_EQ(b.jaw.open_angle_deg, a.jaw.open_angle_deg);
  EXPECT_EQ(b.jaw.hinge_max_error_cm, a.jaw.hinge_max_error_cm);
  ASSERT_EQ(b.jaw.shapes.size(), 1u);
  EXPECT_EQ(b.jaw.shapes[0].name, "jawOpen");
  EXPECT_EQ(b.jaw.shapes[0].R, a.jaw.shapes[0].R);
  EXPECT_EQ(b.jaw.shapes[0].t, a.jaw.shapes[0].t);
  EXPECT_EQ(b.jaw.shapes[0].fit_rms_cm, a.jaw.shapes[0].fit_rms_cm);
  ASSERT_EQ(b.muscles.size(), 1u);
  EXPECT_EQ(b.muscles[0].name, a.muscles[0].name);
  EXPECT_EQ(b.muscles[0].type, MuscleType::Sphincter);
  EXPECT_EQ(b.muscles[0].curve, a.muscles[0].curve);
  EXPECT_EQ(b.muscles[0].radius, a.muscles[0].radius);
  EXPECT_EQ(b.activation, a.activation);
  EXPECT_EQ(b.teeth_upper.V, a.teeth_upper.V);
  EXPECT_EQ(b.teeth_lower.F, a.teeth_lower.F);
  for (auto [sa, sb] : {std::pair{&a.hr, &b.hr}, std::pair{&a.lr, &b.lr}}) {
    EXPECT_EQ(sb->mesh.X, sa->mesh.X);
    EXPECT_EQ(sb->mesh.T, sa->mesh.T);
    EXPECT_EQ(sb->muscle, sa->muscle);
    EXPECT_EQ(sb->muscle_fraction, sa->muscle_fraction);
    EXPECT_EQ(sb->fibre, sa->fibre);
    EXPECT_EQ(sb->dirichlet, sa->dirichlet);
    EXPECT_EQ(sb->dirichlet_bone, sa->dirichlet_bone);
    EXPECT_EQ(sb->surface.tet, sa->surface.tet);
    EXPECT_EQ(sb->surface.weights, sa->surface.weights);
    EXPECT_EQ(sb->surface.outside, sa->surface.outside);
    EXPECT_EQ(sb->tracks, sa->tracks);
    EXPECT_EQ(sb->track_area, sa->track_area);
  }
  EXPECT_EQ(b.lattice.origin, a.lattice.origin);
  EXPECT_EQ(b.lattice.cell, a.lattice.cell);
  EXPECT_EQ(b.lattice.dims, a.lattice.dims);
  EXPECT_EQ(b.predeform.angle_deg, a.predeform.angle_deg);
  EXPECT_EQ(b.predeform.surface_jaw_weight, a.predeform.surface_jaw_weight);
  EXPECT_EQ(b.predeform.surface_predeformed, a.predeform.surface_predeformed);
}

TEST_F(RigIo, ChecksumIdentifiesTheContentNotTheBuildRecord) {
  const Rig a = make_rig();
  save_rig(a, path("a.rig"));
  const Rig b = load_rig(path("a.rig"));
  EXPECT_EQ(rig_checksum(a), rig_checksum(b));
  // The file's own integrity checksum covers every byte, the build record too.
  const auto bytes = read_bytes(path("a.rig"));
  uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  EXPECT_EQ(stored, fnv1a64(bytes.data() + 24, bytes.size() - 32));

  // A rebuild differs only in its build record: same identity.
  Rig rebuilt = a;
  rebuilt.build_seconds += 3.5;
  rebuilt.source = "/somewhere/else/" + a.source;
  EXPECT_EQ(rig_checksum(rebuilt), rig_checksum(a));

  Rig c = a;
  c.hr.track_area[0] += 1e-3f;
  EXPECT_NE(rig_checksum(c), rig_checksum(a));
}

TEST_F(RigIo, TruncatedFileNamesPathAndProblem) {
  save_rig(make_rig(), path("a.rig"));
  const auto bytes = read_bytes(path("a.rig"));
  const std::string cut = path("cut.rig");
  for (size_t n : {size_t(0), size_t(5), size_t(12), size_t(23), size_t(24), size_t(100),
                   bytes.size() / 2, bytes.size() - 8, bytes.size() - 1}) {
    SCOPED_TRACE(n);
    write_bytes(cut, std::vector<uint8_t>(bytes.begin(), bytes.begin() + long(n)));
    expect_error([&] { load_rig(cut); }, {cut, "truncated"});
  }
}

TEST_F(RigIo, CorruptPayloadFailsChecksum) {
  save_rig(make_rig(), path("a.rig"));
  auto bytes = read_bytes(path("a.rig"));
  bytes[24 + 40] ^= 0x10;
  write_bytes(path("a.rig"), bytes);
  expect_error([&] { load_rig(path("a.rig")); }, {path("a.rig"), "checksum"});
}

TEST_F(RigIo, BadMagicWrongVersionTrailingBytes) {
  save_rig(make_rig(), path("a.rig"));
  const auto good = read_bytes(path("a.rig"));

  auto bytes = good;
  bytes[0] = 'X';
  write_bytes(path("m.rig"), bytes);
  expect_error([&] { load_rig(path("m.rig")); }, {path("m.rig"), "bad magic"});

  bytes = good;
  const uint32_t v2 = 2;
  std::memcpy(bytes.data() + 8, &v2, 4);
  write_bytes(path("v.rig"), bytes);
  expect_error([&] { load_rig(path("v.rig")); }, {path("v.rig"), "version 2 is not supported"});

  bytes = good;
  bytes.push_back(0);
  write_bytes(path("t.rig"), bytes);
  expect_error([&] { load_rig(path("t.rig")); }, {path("t.rig"), "after the checksum"});
}

TEST_F(RigIo, MissingFileNamesPath) {
  expect_error([&] { load_rig(path("nope.rig")); }, {"cannot open '" + path("nope.rig") + "'"});
}

TEST_F(RigIo, SaveRefusesNonFiniteAndLeavesNoFile) {
  Rig r = make_rig();
  r.surface(2, 1) = std::numeric_limits<double>::quiet_NaN();
  expect_error([&] { save_rig(r, path("nan.rig")); }, {path("nan.rig"), "surface", "non-finite"});
  EXPECT_TRUE(fs::is_empty(dir_));  // neither the file nor a temporary

  r = make_rig();
  r.hr.muscle_fraction[1] = std::numeric_limits<float>::infinity();
  expect_error([&] { save_rig(r, path("inf.rig")); }, {"hr.muscle_fraction"});
  EXPECT_TRUE(fs::is_empty(dir_));
}

TEST_F(RigIo, SaveRejectsInconsistentRigs) {
  auto rejects = [&](void (*mutate)(Rig&), const std::string& field) {
    SCOPED_TRACE(field);
    Rig r = make_rig();
    mutate(r);
    expect_error([&] { save_rig(r, path("bad.rig")); }, {path("bad.rig"), field});
    EXPECT_FALSE(fs::exists(path("bad.rig")));
  };
  rejects([](Rig& r) { r.hr.mesh.T(1, 3) = 5; }, "hr.mesh.T");
  rejects([](Rig& r) { r.lr.mesh.T(0, 0) = -1; }, "lr.mesh.T");
  rejects([](Rig& r) { r.surface_tris(0, 2) = 4; }, "surface_tris");
  rejects([](Rig& r) { r.hr.muscle.pop_back(); }, "hr.muscle");
  rejects([](Rig& r) { r.hr.muscle[0] = 1; }, "hr.muscle");
  rejects([](Rig& r) { r.lr.fibre.push_back(0); }, "lr.fibre");
  rejects([](Rig& r) { r.hr.surface.tet[3] = 2; }, "hr.surface.tet");
  rejects([](Rig& r) { r.lr.surface.weights.pop_back(); }, "lr.surface.weights");
  rejects([](Rig& r) { r.blendshape_deltas.pop_back(); }, "blendshape_deltas");
  rejects([](Rig& r) { r.activation.push_back(0); }, "activation");
  rejects([](Rig& r) { r.hr.dirichlet[0] = 5; }, "hr.dirichlet");
  rejects([](Rig& r) { r.lr.dirichlet_bone.push_back(0); }, "lr.dirichlet_bone");
  rejects([](Rig& r) { r.hr.tracks[0] = 4; }, "hr.tracks");
  rejects([](Rig& r) { r.lr.track_area.clear(); }, "lr.track_area");
  rejects([](Rig& r) { r.landmark_vertex.pop_back(); }, "landmark_vertex");
  rejects([](Rig& r) { r.predeform.surface_jaw_weight.pop_back(); },
          "predeform.surface_jaw_weight");
}

TEST_F(RigIo, LoadValidatesContentBehindAValidChecksum) {
  const Rig r = make_rig();
  save_rig(r, path("a.rig"));
  auto bytes = read_bytes(path("a.rig"));
  // First surface coordinate: header, name, units, then rows and cols.
  const size_t at = 24 + (8 + r.name.size()) + (8 + r.units.size()) + 16;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(bytes.data() + at, &nan, 8);
  reseal(bytes);
  write_bytes(path("a.rig"), bytes);
  expect_error([&] { load_rig(path("a.rig")); }, {path("a.rig"), "surface", "non-finite"});
}

// Corruption that slips past the checksum (or a buggy writer) must surface as
// an Error, never as a crash or a huge allocation.
TEST_F(RigIo, EveryResealedByteChangeLoadsOrThrowsError) {
  save_rig(make_rig(), path("a.rig"));
  const auto good = read_bytes(path("a.rig"));
  uint64_t payload_size;
  std::memcpy(&payload_size, good.data() + 16, 8);
  for (size_t i = 24; i < 24 + payload_size; ++i) {
    for (uint8_t x : {uint8_t(0x01), uint8_t(0x80), uint8_t(0xff)}) {
      auto bytes = good;
      bytes[i] ^= x;
      reseal(bytes);
      write_bytes(path("x.rig"), bytes);
      try {
        load_rig(path("x.rig"));
      } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(path("x.rig")), std::string::npos) << e.what();
      }
    }
  }
}

TEST(RigSummary, CountsOfSyntheticRig) {
  const auto s = rig_summary(make_rig());
  EXPECT_EQ(s["name"], "tiny");
  EXPECT_EQ(s["units"], "cm");
  EXPECT_EQ(s["source"], "synthetic");
  EXPECT_EQ(s["build_seconds"], 1.25);
  EXPECT_EQ(s["hr_tets"], 2);
  EXPECT_EQ(s["hr_vertices"], 5);
  EXPECT_EQ(s["lr_tets"], 1);
  EXPECT_EQ(s["lr_vertices"], 4);
  EXPECT_EQ(s["hr_over_lr_tets"], 2.0);
  EXPECT_EQ(s["surface_vertices"], 4);
  EXPECT_EQ(s["surface_triangles"], 2);
  EXPECT_EQ(s["embedded_outside_hr"], 1);
  EXPECT_EQ(s["embedded_outside_lr"], 2);
  EXPECT_EQ(s["inverted_tets"], 0);
  EXPECT_NEAR(s["hr_volume_cm3"].get<double>(), 0.5, 1e-12);
  EXPECT_NEAR(s["lr_volume_cm3"].get<double>(), 1.0 / 6.0, 1e-12);
  // The corner tet has three right dihedral angles and three of acos(1/√3).
  EXPECT_NEAR(s["lr_min_dihedral_deg"].get<double>(), std::acos(1 / std::sqrt(3.0)) * 180 / M_PI,
              1e-9);
  EXPECT_NEAR(s["lr_max_dihedral_deg"].get<double>(), 90.0, 1e-9);
  EXPECT_GT(s["hr_min_dihedral_deg"].get<double>(), 0.0);
  EXPECT_EQ(s["muscles"], 1);
  EXPECT_EQ(s["muscle_names"], nlohmann::json::array({"zygomaticus"}));
  EXPECT_EQ(s["muscle_tets_hr"], 1);
  EXPECT_EQ(s["muscle_tets_lr"], 1);
  EXPECT_EQ(s["muscle_tets_hr_per_muscle"]["zygomaticus"], 1);
  EXPECT_EQ(s["muscle_tets_lr_per_muscle"]["zygomaticus"], 1);
  EXPECT_EQ(s["dirichlet_nodes_hr"], 3);
  EXPECT_EQ(s["dirichlet_nodes_lr"], 1);
  EXPECT_EQ(s["dirichlet_jaw_nodes_hr"], 2);
  EXPECT_EQ(s["dirichlet_jaw_nodes_lr"], 1);
  EXPECT_EQ(s["tracks_hr"], 2);
  EXPECT_EQ(s["tracks_lr"], 1);
  EXPECT_EQ(s["blendshapes"], 2);
  EXPECT_EQ(s["blendshape_names"], nlohmann::json::array({"jawOpen", "smile"}));
  EXPECT_EQ(s["landmarks"], 2);
  EXPECT_EQ(s["lattice_cell_cm"], 0.75);
  EXPECT_EQ(s["lattice_dims"], nlohmann::json::array({4, 5, 6}));
  EXPECT_EQ(s["predeform_angle_deg"], 12.0);
  const auto& jaw = s["jaw"];
  EXPECT_EQ(jaw["pivot"], nlohmann::json::array({0.1, -0.2, 0.3}));
  EXPECT_EQ(jaw["axis"], nlohmann::json::array({1.0, 0.0, 0.0}));
  EXPECT_EQ(jaw["open_angle_deg"], 18.5);
  EXPECT_EQ(jaw["hinge_max_error_cm"], 0.02);
  ASSERT_EQ(jaw["shapes"].size(), 1u);
  EXPECT_EQ(jaw["shapes"][0]["name"], "jawOpen");
  EXPECT_EQ(jaw["shapes"][0]["fit_rms_cm"], 0.003);
}
