// The C ABI (libfacesr.so through facesr.h): argument checking and status
// codes, struct_size compatibility, shared rig and model, sync/async parity,
// file and device errors, springs and spheres, reset, blendshape names.
// The engine is used only to write the test's rig and model files.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "facesr.h"
#include "rig/rig_io.h"
#include "sr/sr_geometry.h"
#include "sr/sr_model.h"
#include "test_support.h"
#include "train/model_export.h"
#include "train/sr_network.h"

namespace {

namespace fs = std::filesystem;

std::string message() { return facesr_last_error_message(); }

// The call fails with `code` and leaves a message naming the function.
#define EXPECT_STATUS(code, call)                                                              \
  do {                                                                                         \
    const facesr_status s_ = (call);                                                           \
    EXPECT_EQ(s_, code) << #call << ": " << facesr_status_name(s_) << ": " << message();       \
    if ((code) != FACESR_OK) EXPECT_NE(message().find("facesr_"), std::string::npos) << #call; \
  } while (0)
#define ASSERT_OK(call)                                                                       \
  do {                                                                                        \
    const facesr_status s_ = (call);                                                          \
    ASSERT_EQ(s_, FACESR_OK) << #call << ": " << facesr_status_name(s_) << ": " << message(); \
  } while (0)

// Files shared by every test: the coarse procedural rig, a small network
// with random weights for it, and broken variants. ctest runs each test in a
// process of its own, so they are made once per build of this binary (about
// 5 s) into a folder beside it named for the binary's time stamp.
struct Files {
  fs::path dir;
  std::string rig, model, other_rig_model, corrupt_model, truncated_rig;

  Files() {
    dir = cache_dir();
    rig = (dir / "p.rig").string();
    model = (dir / "p.fsm").string();
    other_rig_model = (dir / "other.fsm").string();
    corrupt_model = (dir / "corrupt.fsm").string();
    truncated_rig = (dir / "truncated.rig").string();
    if (fs::exists(dir / "complete")) return;
    // Made under a private name and renamed into place, so that concurrent
    // test processes never see a half-written set.
    const fs::path tmp = dir.string() + ".tmp" + std::to_string(::getpid());
    fs::remove_all(tmp);
    fs::create_directories(tmp);
    make(tmp);
    std::ofstream(tmp / "complete").put('\n');
    std::error_code ec;
    fs::rename(tmp, dir, ec);
    if (ec) fs::remove_all(tmp, ec);  // another process was first
    for (const auto& e : fs::directory_iterator(dir.parent_path(), ec))
      if (e.path() != dir && e.path().filename().string().rfind("capi_test_files_", 0) == 0 &&
          e.path().string().find(".tmp") == std::string::npos)
        fs::remove_all(e.path(), ec);  // sets of earlier builds
  }

  static fs::path cache_dir() {
    std::error_code ec;
    const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
    if (ec) return fs::temp_directory_path() / ("facesr_capi_" + std::to_string(::getpid()));
    const auto stamp = uint64_t(fs::last_write_time(exe, ec).time_since_epoch().count());
    return exe.parent_path() / ("capi_test_files_" + std::to_string(stamp));
  }

  static void make(const fs::path& d) {
    using namespace facesr;
    const Rig& r = fixtures::procedural_rig();
    save_rig(r, (d / "p.rig").string());
    SrModel m;
    m.arch.pe_dim = 8;
    m.arch.encoder_dims = {8, 8};
    m.arch.weight_hidden = {8};
    m.arch.recon_hidden = {16};
    m.rig_name = r.name;
    m.rig_checksum = rig_checksum(r);
    m.geometry = build_sr_geometry(r);
    m.num_lr = m.geometry.num_lr;
    m.num_hr = m.geometry.num_hr;
    m.arch.input_scale = 0.2;
    m.arch.output_scale = 0.3;
    set_coordinate_frame(m.arch, m.geometry);
    torch::manual_seed(11);
    SrNetwork net(m.arch, m.geometry);
    export_parameters(*net, m);
    save_sr_model((d / "p.fsm").string(), m);
    m.rig_checksum ^= 0x5a5a;  // "trained on another rig"
    save_sr_model((d / "other.fsm").string(), m);

    std::vector<char> bytes = read(d / "p.fsm");
    bytes[bytes.size() / 2] ^= 0x10;
    write(d / "corrupt.fsm", bytes);
    bytes = read(d / "p.rig");
    bytes.resize(bytes.size() * 2 / 3);
    write(d / "truncated.rig", bytes);
  }
  static std::vector<char> read(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    return std::vector<char>(std::istreambuf_iterator<char>(in), {});
  }
  static void write(const fs::path& p, const std::vector<char>& b) {
    std::ofstream(p, std::ios::binary).write(b.data(), std::streamsize(b.size()));
  }
};

const Files& files() {
  static const Files f;
  return f;
}

// One loaded rig and model, freed at the end of the test.
class Capi : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_OK(facesr_rig_load(files().rig.c_str(), &rig_));
    ASSERT_OK(facesr_model_load(files().model.c_str(), &model_));
    info_.struct_size = sizeof info_;
    ASSERT_OK(facesr_rig_get_info(rig_, &info_));
    n_ = 3 * int64_t(info_.num_surface_vertices);
  }
  void TearDown() override {
    for (facesr_context* c : contexts_) facesr_context_destroy(c);
    facesr_model_free(model_);
    facesr_rig_free(rig_);
  }

  facesr_context* context(int32_t inference = FACESR_INFERENCE_CPU) {
    facesr_context_def def = facesr_default_context_def();
    def.inference = inference;
    facesr_context* c = nullptr;
    const facesr_status s = facesr_context_create(rig_, model_, &def, &c);
    EXPECT_EQ(s, FACESR_OK) << facesr_status_name(s) << ": " << message();
    if (c) contexts_.push_back(c);
    return c;
  }
  std::vector<float> positions(const facesr_context* c) const {
    std::vector<float> p(static_cast<size_t>(n_));
    EXPECT_EQ(facesr_get_positions(c, p.data(), n_), FACESR_OK) << message();
    return p;
  }
  std::vector<float> embedded(const facesr_context* c) const {
    std::vector<float> p(static_cast<size_t>(n_));
    EXPECT_EQ(facesr_get_embedded_positions(c, p.data(), n_), FACESR_OK) << message();
    return p;
  }
  std::vector<float> rest() const {
    std::vector<float> p(static_cast<size_t>(n_));
    EXPECT_EQ(facesr_rig_get_rest_positions(rig_, p.data(), n_), FACESR_OK) << message();
    return p;
  }
  int32_t index(const char* name) const {
    int32_t i = -1;
    EXPECT_EQ(facesr_rig_blendshape_index(rig_, name, &i), FACESR_OK) << message();
    return i;
  }
  // Frame f of a short performance: the jaw opening and a smile coming in.
  void set_controls(facesr_context* c, int f) const {
    std::vector<float> w(size_t(info_.num_blendshapes), 0.0f);
    w[size_t(index("jawOpen"))] = 0.15f * float(f % 5);
    w[size_t(index("mouthSmile_L"))] = 0.1f * float(f);
    ASSERT_OK(facesr_set_weights(c, w.data(), int64_t(w.size())));
  }

  facesr_rig* rig_ = nullptr;
  facesr_model* model_ = nullptr;
  facesr_rig_info info_{};
  int64_t n_ = 0;
  std::vector<facesr_context*> contexts_;
};

double max_diff(const std::vector<float>& a, const std::vector<float>& b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d = std::max(d, std::fabs(double(a[i]) - b[i]));
  return d;
}

TEST(CapiBasics, VersionsAndStatusNames) {
  EXPECT_EQ(facesr_abi_version(), uint32_t(FACESR_ABI_VERSION));
  EXPECT_STREQ(facesr_version_string(), "facesr 0.1.0");
  const char* names[] = {
      "FACESR_OK",          "FACESR_ERROR_NULL_ARGUMENT", "FACESR_ERROR_INVALID_ARGUMENT", "FACESR_ERROR_BUFFER_SIZE",
      "FACESR_ERROR_FILE",  "FACESR_ERROR_MISMATCH",      "FACESR_ERROR_DEVICE",           "FACESR_ERROR_NOT_FOUND",
      "FACESR_ERROR_STATE", "FACESR_ERROR_SIMULATION",    "FACESR_ERROR_INTERNAL"};
  for (int s = 0; s <= FACESR_ERROR_INTERNAL; ++s) EXPECT_STREQ(facesr_status_name(s), names[s]);
  EXPECT_STREQ(facesr_status_name(11), "unknown");
  EXPECT_STREQ(facesr_status_name(-3), "unknown");
}

TEST(CapiBasics, ErrorMessageIsPerThreadAndKeptUntilTheNextFailure) {
  facesr_rig* rig = nullptr;
  ASSERT_EQ(facesr_rig_load(nullptr, &rig), FACESR_ERROR_NULL_ARGUMENT);
  const std::string mine = message();
  EXPECT_NE(mine.find("facesr_rig_load: path"), std::string::npos) << mine;
  std::string other = "unset";
  std::thread([&] { other = facesr_last_error_message(); }).join();
  EXPECT_EQ(other, "");
  EXPECT_EQ(facesr_abi_version(), uint32_t(FACESR_ABI_VERSION));  // success leaves the message alone
  EXPECT_EQ(message(), mine);
}

TEST_F(Capi, EveryFunctionRejectsNullArguments) {
  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  std::vector<float> buf(static_cast<size_t>(n_));
  std::vector<int32_t> tris(3 * size_t(info_.num_surface_triangles));
  const float v3[3] = {0, 0, 0};
  const float r9[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  facesr_model_info minfo{};
  minfo.struct_size = sizeof minfo;
  facesr_frame_stats st{};
  st.struct_size = sizeof st;
  facesr_spring_def spring = facesr_default_spring_def();
  facesr_sphere_def sphere = facesr_default_sphere_def();
  char name[16];
  int32_t i32 = 0;
  int64_t i64 = 0;
  facesr_rig* r = nullptr;
  facesr_model* m = nullptr;
  facesr_context* cc = nullptr;
  const facesr_status N = FACESR_ERROR_NULL_ARGUMENT;

  EXPECT_STATUS(N, facesr_rig_load(files().rig.c_str(), nullptr));
  EXPECT_STATUS(N, facesr_rig_load(nullptr, &r));
  EXPECT_STATUS(N, facesr_rig_get_info(nullptr, &info_));
  EXPECT_STATUS(N, facesr_rig_get_info(rig_, nullptr));
  EXPECT_STATUS(N, facesr_rig_blendshape_name(nullptr, 0, name, sizeof name, &i32));
  EXPECT_STATUS(N, facesr_rig_blendshape_name(rig_, 0, nullptr, sizeof name, &i32));
  EXPECT_STATUS(N, facesr_rig_blendshape_index(nullptr, "jawOpen", &i32));
  EXPECT_STATUS(N, facesr_rig_blendshape_index(rig_, nullptr, &i32));
  EXPECT_STATUS(N, facesr_rig_blendshape_index(rig_, "jawOpen", nullptr));
  EXPECT_STATUS(N, facesr_rig_get_triangles(nullptr, tris.data(), int64_t(tris.size())));
  EXPECT_STATUS(N, facesr_rig_get_triangles(rig_, nullptr, int64_t(tris.size())));
  EXPECT_STATUS(N, facesr_rig_get_rest_positions(nullptr, buf.data(), n_));
  EXPECT_STATUS(N, facesr_rig_get_rest_positions(rig_, nullptr, n_));
  EXPECT_STATUS(N, facesr_model_load(files().model.c_str(), nullptr));
  EXPECT_STATUS(N, facesr_model_load(nullptr, &m));
  EXPECT_STATUS(N, facesr_model_get_info(nullptr, &minfo));
  EXPECT_STATUS(N, facesr_model_get_info(model_, nullptr));
  EXPECT_STATUS(N, facesr_context_create(nullptr, model_, nullptr, &cc));
  EXPECT_STATUS(N, facesr_context_create(rig_, nullptr, nullptr, &cc));
  EXPECT_STATUS(N, facesr_context_create(rig_, model_, nullptr, nullptr));
  EXPECT_STATUS(N, facesr_context_reset(nullptr));
  EXPECT_STATUS(N, facesr_set_weight(nullptr, 0, 0.5f));
  EXPECT_STATUS(N, facesr_set_weight_by_name(nullptr, "jawOpen", 0.5f));
  EXPECT_STATUS(N, facesr_set_weight_by_name(c, nullptr, 0.5f));
  EXPECT_STATUS(N, facesr_set_weights(nullptr, buf.data(), info_.num_blendshapes));
  EXPECT_STATUS(N, facesr_set_weights(c, nullptr, info_.num_blendshapes));
  EXPECT_STATUS(N, facesr_set_jaw_transform(nullptr, r9, v3));
  EXPECT_STATUS(N, facesr_set_jaw_transform(c, nullptr, v3));
  EXPECT_STATUS(N, facesr_set_jaw_transform(c, r9, nullptr));
  EXPECT_STATUS(N, facesr_clear_jaw_transform(nullptr));
  EXPECT_STATUS(N, facesr_add_spring(nullptr, &spring, &i32));
  EXPECT_STATUS(N, facesr_add_spring(c, nullptr, &i32));
  EXPECT_STATUS(N, facesr_add_spring(c, &spring, nullptr));
  EXPECT_STATUS(N, facesr_move_spring(nullptr, 1, v3));
  EXPECT_STATUS(N, facesr_move_spring(c, 1, nullptr));
  EXPECT_STATUS(N, facesr_remove_spring(nullptr, 1));
  EXPECT_STATUS(N, facesr_add_sphere(nullptr, &sphere, &i32));
  EXPECT_STATUS(N, facesr_add_sphere(c, nullptr, &i32));
  EXPECT_STATUS(N, facesr_add_sphere(c, &sphere, nullptr));
  EXPECT_STATUS(N, facesr_move_sphere(nullptr, 1, v3));
  EXPECT_STATUS(N, facesr_move_sphere(c, 1, nullptr));
  EXPECT_STATUS(N, facesr_remove_sphere(nullptr, 1));
  EXPECT_STATUS(N, facesr_step(nullptr));
  EXPECT_STATUS(N, facesr_step_async(nullptr));
  EXPECT_STATUS(N, facesr_wait(nullptr, &i64));
  EXPECT_STATUS(N, facesr_pending_frames(nullptr, &i32));
  EXPECT_STATUS(N, facesr_pending_frames(c, nullptr));
  EXPECT_STATUS(N, facesr_get_positions(nullptr, buf.data(), n_));
  EXPECT_STATUS(N, facesr_get_positions(c, nullptr, n_));
  EXPECT_STATUS(N, facesr_get_normals(nullptr, buf.data(), n_));
  EXPECT_STATUS(N, facesr_get_normals(c, nullptr, n_));
  EXPECT_STATUS(N, facesr_get_embedded_positions(nullptr, buf.data(), n_));
  EXPECT_STATUS(N, facesr_get_embedded_positions(c, nullptr, n_));
  EXPECT_STATUS(N, facesr_get_frame_stats(nullptr, &st));
  EXPECT_STATUS(N, facesr_get_frame_stats(c, nullptr));
  EXPECT_EQ(r, nullptr);
  EXPECT_EQ(m, nullptr);
  EXPECT_EQ(cc, nullptr);
  facesr_rig_free(nullptr);
  facesr_model_free(nullptr);
  facesr_context_destroy(nullptr);
  ASSERT_OK(facesr_step(c));  // nothing above touched the context
}

TEST_F(Capi, EveryBufferCountIsChecked) {
  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  const int64_t nt = 3 * int64_t(info_.num_surface_triangles);
  std::vector<float> big(size_t(n_) + 16);
  std::vector<int32_t> tris(size_t(nt) + 1);
  for (const int64_t wrong : {int64_t(0), int64_t(-1), nt - 1, nt + 1})
    EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_rig_get_triangles(rig_, tris.data(), wrong));
  EXPECT_NE(message().find(std::to_string(nt)), std::string::npos) << message();
  for (const int64_t wrong : {int64_t(0), n_ / 3, n_ - 1, n_ + 3}) {
    EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_rig_get_rest_positions(rig_, big.data(), wrong));
    EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_positions(c, big.data(), wrong));
    EXPECT_NE(message().find(std::to_string(n_)), std::string::npos) << message();
    EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_normals(c, big.data(), wrong));
    EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_embedded_positions(c, big.data(), wrong));
  }
  const int64_t nb = info_.num_blendshapes;
  std::vector<float> w(size_t(nb) + 1, 0.0f);
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_set_weights(c, w.data(), nb - 1));
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_set_weights(c, w.data(), nb + 1));
  EXPECT_STATUS(FACESR_OK, facesr_set_weights(c, w.data(), nb));
}

TEST_F(Capi, InvalidValuesAreRejectedAndChangeNothing) {
  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  const float I[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, -0.1f, 0.05f};
  const float scaled[9] = {2, 0, 0, 0, 1, 0, 0, 0, 1}, mirror[9] = {-1, 0, 0, 0, 1, 0, 0, 0, 1};
  const float nan3[3] = {NAN, 0, 0};
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(c, 0, NAN));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(c, 0, INFINITY));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(c, 0, -0.15f));  // beyond the capture tolerance
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(c, info_.num_blendshapes, 0.5f));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight_by_name(c, "jawOpen", 1.15f));
  EXPECT_STATUS(FACESR_ERROR_NOT_FOUND, facesr_set_weight_by_name(c, "JawOpen", 0.5f));
  EXPECT_NE(message().find("'JawOpen'"), std::string::npos) << message();
  std::vector<float> w(size_t(info_.num_blendshapes), 0.5f);
  w.back() = NAN;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weights(c, w.data(), int64_t(w.size())));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_jaw_transform(c, scaled, t));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_jaw_transform(c, mirror, t));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_jaw_transform(c, I, nan3));
  // None of those took effect: the face stays at rest.
  ASSERT_OK(facesr_step(c));
  EXPECT_LT(max_diff(embedded(c), rest()), 1e-3);
  ASSERT_OK(facesr_set_jaw_transform(c, I, t));
  ASSERT_OK(facesr_clear_jaw_transform(c));
}

TEST_F(Capi, InfoStructsFillOnlyTheFieldsThatFit) {
  // An older caller's struct ends after num_surface_vertices; the bytes after
  // it are not the caller's and must stay untouched.
  struct {
    facesr_rig_info info;
    unsigned char guard[16];
  } old;
  std::memset(&old, 0xAB, sizeof old);
  old.info.struct_size = uint32_t(offsetof(facesr_rig_info, num_surface_vertices) + sizeof(int32_t));
  ASSERT_OK(facesr_rig_get_info(rig_, &old.info));
  EXPECT_EQ(old.info.num_blendshapes, info_.num_blendshapes);
  EXPECT_EQ(old.info.num_surface_vertices, info_.num_surface_vertices);
  const unsigned char* bytes = reinterpret_cast<const unsigned char*>(&old);
  for (size_t i = old.info.struct_size; i < sizeof old; ++i) ASSERT_EQ(bytes[i], 0xAB) << "byte " << i;

  // A newer caller's bigger struct: every known field filled, the rest left alone.
  std::memset(&old, 0xAB, sizeof old);
  old.info.struct_size = uint32_t(sizeof old);
  ASSERT_OK(facesr_rig_get_info(rig_, &old.info));
  EXPECT_EQ(old.info.checksum, info_.checksum);
  EXPECT_EQ(old.info.num_muscles, info_.num_muscles);
  for (unsigned char g : old.guard) EXPECT_EQ(g, 0xAB);

  facesr_model_info m;
  std::memset(&m, 0xCD, sizeof m);
  m.struct_size = uint32_t(offsetof(facesr_model_info, rig_checksum) + sizeof(uint64_t));
  ASSERT_OK(facesr_model_get_info(model_, &m));
  EXPECT_EQ(m.rig_checksum, info_.checksum);
  int32_t untouched;
  std::memset(&untouched, 0xCD, sizeof untouched);
  EXPECT_EQ(m.num_lr_nodes, untouched);
  m.struct_size = sizeof m;
  ASSERT_OK(facesr_model_get_info(model_, &m));
  EXPECT_EQ(m.num_lr_nodes, info_.num_lr_nodes);
  EXPECT_EQ(m.num_surface_vertices, info_.num_surface_vertices);
  EXPECT_GT(m.num_parameters, 0);

  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  ASSERT_OK(facesr_step(c));
  facesr_frame_stats st;
  std::memset(&st, 0xEE, sizeof st);
  st.struct_size = uint32_t(offsetof(facesr_frame_stats, frame) + sizeof(int64_t));
  ASSERT_OK(facesr_get_frame_stats(c, &st));
  EXPECT_EQ(st.frame, 0);
  float untouched_f;
  std::memset(&untouched_f, 0xEE, sizeof untouched_f);
  EXPECT_EQ(std::memcmp(&st.simulation_ms, &untouched_f, sizeof(float)), 0);

  for (uint32_t bad : {0u, 1u, 3u}) {
    facesr_rig_info i{};
    i.struct_size = bad;
    EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_get_info(rig_, &i));
    facesr_model_info mi{};
    mi.struct_size = bad;
    EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_model_get_info(model_, &mi));
    facesr_frame_stats s{};
    s.struct_size = bad;
    EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_get_frame_stats(c, &s));
  }
}

TEST_F(Capi, DefinitionsSmallerThanVersionOneAreInvalid) {
  facesr_context_def def = facesr_default_context_def();
  EXPECT_EQ(def.struct_size, sizeof def);
  EXPECT_EQ(def.device_index, -1);
  EXPECT_EQ(def.device_name, nullptr);
  EXPECT_EQ(def.solver, FACESR_SOLVER_REALTIME);
  EXPECT_EQ(def.inference, FACESR_INFERENCE_OPENCL);
  EXPECT_EQ(def.split_device, 0);
  EXPECT_EQ(def.lr_precision, FACESR_PRECISION_AUTO);
  def.inference = FACESR_INFERENCE_CPU;
  facesr_context* c = nullptr;
  // Version 1 ended after `inference`; split_device came later.
  const uint32_t v1 = uint32_t(offsetof(facesr_context_def, inference) + sizeof(int32_t));
  for (uint32_t bad : {0u, 4u, v1 - 4}) {
    def.struct_size = bad;
    EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig_, model_, &def, &c));
    EXPECT_EQ(c, nullptr);
  }
  // A version-1 caller: the fields it does not know keep their defaults.
  def.struct_size = v1;
  def.split_device = 7;  // beyond its struct_size, so not this caller's: ignored
  ASSERT_OK(facesr_context_create(rig_, model_, &def, &c));
  contexts_.push_back(c);
  def.split_device = 0;
  // A version-2 caller (up to split_device): lr_precision is not its own.
  def.struct_size = uint32_t(offsetof(facesr_context_def, split_device) + sizeof(int32_t));
  def.lr_precision = 99;
  ASSERT_OK(facesr_context_create(rig_, model_, &def, &c));
  contexts_.push_back(c);
  def.lr_precision = FACESR_PRECISION_AUTO;
  // A newer caller's bigger definition is read up to what this library knows.
  struct {
    facesr_context_def def;
    int32_t newer_field;
  } newer{};
  newer.def = facesr_default_context_def();
  newer.def.inference = FACESR_INFERENCE_CPU;
  newer.def.struct_size = sizeof newer;
  newer.newer_field = 42;
  ASSERT_OK(facesr_context_create(rig_, model_, &newer.def, &c));
  contexts_.push_back(c);

  facesr_spring_def spring = facesr_default_spring_def();
  EXPECT_EQ(spring.vertex, -1);  // must be chosen
  EXPECT_GT(spring.stiffness, 0);
  spring.vertex = 0;
  spring.struct_size = sizeof spring - 1;
  int32_t id = -1;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_spring(c, &spring, &id));
  EXPECT_EQ(id, 0);
  facesr_sphere_def sphere = facesr_default_sphere_def();
  EXPECT_GT(sphere.radius, 0);
  EXPECT_GT(sphere.stiffness, 0);
  sphere.struct_size = 0;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_sphere(c, &sphere, &id));
  facesr_context_def bad = facesr_default_context_def();
  bad.solver = 2;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig_, model_, &bad, &c));
  bad = facesr_default_context_def();
  bad.inference = -1;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig_, model_, &bad, &c));
  bad = facesr_default_context_def();
  bad.lr_precision = 3;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig_, model_, &bad, &c));
  EXPECT_NE(message().find("lr_precision 3"), std::string::npos) << message();
  bad = facesr_default_context_def();
  bad.device_index = -2;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig_, model_, &bad, &c));
}

TEST_F(Capi, TwoContextsOnTwoThreadsShareOneRigAndModel) {
  facesr_context* a = context();
  facesr_context* b = context();
  ASSERT_TRUE(a && b);
  // The contexts keep what they need: the handles may go first.
  facesr_rig_free(rig_);
  facesr_model_free(model_);
  rig_ = nullptr;
  model_ = nullptr;
  constexpr int kFrames = 4;
  std::vector<std::vector<float>> pa(kFrames), pb(kFrames);
  auto run = [&](facesr_context* c, std::vector<std::vector<float>>& out, float jaw) {
    for (int f = 0; f < kFrames; ++f) {
      EXPECT_EQ(facesr_set_weight_by_name(c, "jawOpen", jaw * float(f)), FACESR_OK);
      EXPECT_EQ(facesr_set_weight_by_name(c, "mouthSmile_L", 0.2f), FACESR_OK);
      if (facesr_step(c) != FACESR_OK) return;
      out[size_t(f)].resize(size_t(n_));
      EXPECT_EQ(facesr_get_positions(c, out[size_t(f)].data(), n_), FACESR_OK);
    }
  };
  std::thread ta(run, a, std::ref(pa), 0.2f), tb(run, b, std::ref(pb), 0.2f);
  ta.join();
  tb.join();
  for (int f = 0; f < kFrames; ++f) {
    ASSERT_EQ(pa[size_t(f)].size(), size_t(n_)) << "frame " << f;
    EXPECT_EQ(pa[size_t(f)], pb[size_t(f)]) << "frame " << f << ": max diff " << max_diff(pa[size_t(f)], pb[size_t(f)]);
  }
  EXPECT_GT(max_diff(pa[kFrames - 1], pa[0]), 0.01) << "the controls should move the face";
}

// split_device through the ABI: half the device each for the simulation and
// the OpenCL inference, stepped asynchronously, gives the surfaces of a
// whole-device context stepped synchronously.
TEST_F(Capi, SplitDeviceAsyncGivesTheSyncSurfaces) {
  facesr_context* sync = context(FACESR_INFERENCE_OPENCL);
  ASSERT_TRUE(sync);
  facesr_context_def def = facesr_default_context_def();
  def.inference = FACESR_INFERENCE_OPENCL;
  def.split_device = 1;
  facesr_context* split = nullptr;
  ASSERT_OK(facesr_context_create(rig_, model_, &def, &split));
  contexts_.push_back(split);
  constexpr int kFrames = 4;
  std::vector<std::vector<float>> want, got;
  int64_t frame = -1;
  int32_t pending = 0;
  for (int f = 0; f < kFrames; ++f) {
    set_controls(sync, f);
    ASSERT_OK(facesr_step(sync));
    want.push_back(positions(sync));
    set_controls(split, f);
    ASSERT_OK(facesr_step_async(split));
    ASSERT_OK(facesr_pending_frames(split, &pending));
    if (pending == 2) {
      ASSERT_OK(facesr_wait(split, &frame));
      got.push_back(positions(split));
    }
  }
  ASSERT_OK(facesr_wait(split, &frame));
  got.push_back(positions(split));
  ASSERT_EQ(got.size(), want.size());
  for (size_t f = 0; f < want.size(); ++f) EXPECT_EQ(got[f], want[f]) << "frame " << f;
}

TEST_F(Capi, AsyncSteppingGivesTheSyncSurfaces) {
  facesr_context* sync = context();
  facesr_context* async = context();
  ASSERT_TRUE(sync && async);
  constexpr int kFrames = 6;
  std::vector<std::vector<float>> want(kFrames), got(kFrames);
  for (int f = 0; f < kFrames; ++f) {
    set_controls(sync, f);
    ASSERT_OK(facesr_step(sync));
    want[size_t(f)] = positions(sync);
  }
  // A game tick: submit this frame, show the previous one.
  int64_t frame = -1;
  int32_t pending = 0;
  for (int f = 0; f < kFrames; ++f) {
    set_controls(async, f);
    ASSERT_OK(facesr_step_async(async));
    ASSERT_OK(facesr_pending_frames(async, &pending));
    if (f == 0) {
      EXPECT_EQ(pending, 1);
      continue;
    }
    ASSERT_EQ(pending, 2);
    EXPECT_STATUS(FACESR_ERROR_STATE, facesr_step_async(async));
    EXPECT_STATUS(FACESR_ERROR_STATE, facesr_step(async));
    ASSERT_OK(facesr_wait(async, &frame));
    EXPECT_EQ(frame, f - 1);
    got[size_t(frame)] = positions(async);
  }
  ASSERT_OK(facesr_wait(async, &frame));
  EXPECT_EQ(frame, kFrames - 1);
  got[size_t(frame)] = positions(async);
  EXPECT_STATUS(FACESR_ERROR_STATE, facesr_wait(async, &frame));
  facesr_frame_stats st{};
  st.struct_size = sizeof st;
  ASSERT_OK(facesr_get_frame_stats(async, &st));
  EXPECT_EQ(st.frame, kFrames - 1);
  EXPECT_GT(st.total_ms, 0);
  for (int f = 0; f < kFrames; ++f)
    EXPECT_EQ(got[size_t(f)], want[size_t(f)])
        << "frame " << f << ": max diff " << max_diff(got[size_t(f)], want[size_t(f)]);
  // Destroying with frames in flight waits for them.
  ASSERT_OK(facesr_step_async(async));
  ASSERT_OK(facesr_step_async(async));
}

TEST_F(Capi, ModelOfAnotherRigIsAMismatch) {
  facesr_model* other = nullptr;
  ASSERT_OK(facesr_model_load(files().other_rig_model.c_str(), &other));
  facesr_context_def def = facesr_default_context_def();
  def.inference = FACESR_INFERENCE_CPU;
  facesr_context* c = nullptr;
  EXPECT_STATUS(FACESR_ERROR_MISMATCH, facesr_context_create(rig_, other, &def, &c));
  EXPECT_EQ(c, nullptr);
  EXPECT_NE(message().find("checksum"), std::string::npos) << message();
  facesr_model_free(other);
}

TEST_F(Capi, MissingCorruptAndWrongFilesAreFileErrors) {
  facesr_rig* r = nullptr;
  facesr_model* m = nullptr;
  const std::string missing = (files().dir / "missing.rig").string();
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load(missing.c_str(), &r));
  EXPECT_NE(message().find(missing), std::string::npos) << message();
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load(files().truncated_rig.c_str(), &r));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load(files().model.c_str(), &r));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load("", &r));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load(files().dir.string().c_str(), &r));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_model_load(files().corrupt_model.c_str(), &m));
  EXPECT_NE(message().find("corrupt"), std::string::npos) << message();
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_model_load(files().rig.c_str(), &m));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_model_load((files().dir / "missing.fsm").string().c_str(), &m));
  EXPECT_EQ(r, nullptr);
  EXPECT_EQ(m, nullptr);
}

TEST_F(Capi, UnknownDevicesAreDeviceErrors) {
  facesr_context_def def = facesr_default_context_def();
  def.inference = FACESR_INFERENCE_CPU;
  facesr_context* c = nullptr;
  def.device_name = "no-such-opencl-device";
  EXPECT_STATUS(FACESR_ERROR_DEVICE, facesr_context_create(rig_, model_, &def, &c));
  EXPECT_NE(message().find("no-such-opencl-device"), std::string::npos) << message();
  def.device_name = nullptr;
  def.device_index = 9999;
  EXPECT_STATUS(FACESR_ERROR_DEVICE, facesr_context_create(rig_, model_, &def, &c));
  EXPECT_EQ(c, nullptr);
  // Explicit index 0 and an empty name are ordinary selections.
  def.device_index = 0;
  def.device_name = "";
  ASSERT_OK(facesr_context_create(rig_, model_, &def, &c));
  contexts_.push_back(c);
}

TEST_F(Capi, OpenClInferenceWorksOrFailsCleanly) {
  facesr_context_def def = facesr_default_context_def();
  facesr_context* c = nullptr;
  const facesr_status s = facesr_context_create(rig_, model_, &def, &c);
  if (s != FACESR_OK) {
    EXPECT_EQ(c, nullptr);
    EXPECT_NE(message(), "");
    EXPECT_NE(std::string(facesr_status_name(s)), "unknown");
    std::cout << "OpenCL inference unavailable: " << facesr_status_name(s) << ": " << message() << "\n";
    return;
  }
  contexts_.push_back(c);
  ASSERT_OK(facesr_set_weight_by_name(c, "jawOpen", 0.5f));
  ASSERT_OK(facesr_step(c));
  for (float v : positions(c)) ASSERT_TRUE(std::isfinite(v));
}

TEST_F(Capi, SpringsAndSpheresAddMoveRemove) {
  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  const std::vector<float> r = rest();
  // A vertex of soft tissue: the one the jaw moves most.
  ASSERT_OK(facesr_set_weight_by_name(c, "jawOpen", 1.0f));
  ASSERT_OK(facesr_step(c));
  const std::vector<float> open = embedded(c);
  int32_t v = 0;
  double most = 0;
  for (int32_t i = 0; i < info_.num_surface_vertices; ++i) {
    double d = 0;
    for (int k = 0; k < 3; ++k) d += std::pow(double(open[size_t(3 * i + k)]) - r[size_t(3 * i + k)], 2);
    if (d > most) most = d, v = i;
  }
  ASSERT_OK(facesr_context_reset(c));

  facesr_spring_def spring = facesr_default_spring_def();
  int32_t id = -1;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_spring(c, &spring, &id));  // vertex -1
  EXPECT_EQ(id, 0);
  spring.vertex = info_.num_surface_vertices;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_spring(c, &spring, &id));
  spring.vertex = v;
  spring.stiffness = 0;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_spring(c, &spring, &id));
  spring.stiffness = 100;
  spring.target[0] = NAN;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_spring(c, &spring, &id));
  const float pull[3] = {0, 0, 1};  // 1 cm forward of the rest
  for (int k = 0; k < 3; ++k) spring.target[k] = r[size_t(3 * v + k)] + pull[k];
  ASSERT_OK(facesr_add_spring(c, &spring, &id));
  EXPECT_GT(id, 0);
  ASSERT_OK(facesr_step(c));
  const std::vector<float> pulled = embedded(c);
  double along = 0;
  for (int k = 0; k < 3; ++k) along += (double(pulled[size_t(3 * v + k)]) - r[size_t(3 * v + k)]) * pull[k];
  EXPECT_GT(along, 0.05) << "the spring should pull vertex " << v << " toward its target";

  const float target2[3] = {r[size_t(3 * v)], r[size_t(3 * v + 1)], r[size_t(3 * v + 2)]};
  ASSERT_OK(facesr_move_spring(c, id, target2));
  const float nan3[3] = {0, NAN, 0};
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_move_spring(c, id, nan3));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_move_spring(c, id + 100, target2));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_remove_sphere(c, id));  // a spring's id is not a sphere's
  ASSERT_OK(facesr_remove_spring(c, id));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_remove_spring(c, id));
  EXPECT_NE(message().find(std::to_string(id)), std::string::npos) << message();

  facesr_sphere_def sphere = facesr_default_sphere_def();
  for (int k = 0; k < 3; ++k) sphere.centre[k] = r[size_t(3 * v + k)];
  sphere.radius = 0;
  int32_t sid = -1;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_sphere(c, &sphere, &sid));
  sphere.radius = 1;
  sphere.stiffness = -5;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_add_sphere(c, &sphere, &sid));
  sphere.stiffness = 200;
  ASSERT_OK(facesr_add_sphere(c, &sphere, &sid));
  EXPECT_GT(sid, id) << "ids are never reused";
  ASSERT_OK(facesr_step(c));
  const float far[3] = {1e3f, 1e3f, 1e3f};
  ASSERT_OK(facesr_move_sphere(c, sid, far));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_move_sphere(c, sid + 1, far));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_move_spring(c, sid, far));
  ASSERT_OK(facesr_remove_sphere(c, sid));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_remove_sphere(c, sid));
  int32_t next = -1;
  ASSERT_OK(facesr_add_spring(c, &spring, &next));
  EXPECT_GT(next, sid);
}

TEST_F(Capi, ResetReturnsTheRestPose) {
  facesr_context* c = context();
  facesr_context* fresh = context();
  ASSERT_TRUE(c && fresh);
  const std::vector<float> r = rest();
  EXPECT_EQ(positions(c), r);  // before the first step
  EXPECT_EQ(embedded(c), r);
  facesr_spring_def spring = facesr_default_spring_def();
  spring.vertex = 0;
  int32_t id = 0;
  ASSERT_OK(facesr_add_spring(c, &spring, &id));
  for (int f = 0; f < 3; ++f) {
    set_controls(c, f + 1);
    ASSERT_OK(facesr_step(c));
  }
  ASSERT_OK(facesr_step_async(c));
  EXPECT_GT(max_diff(positions(c), r), 0.01);

  ASSERT_OK(facesr_context_reset(c));
  EXPECT_EQ(positions(c), r);
  EXPECT_EQ(embedded(c), r);
  int32_t pending = -1;
  ASSERT_OK(facesr_pending_frames(c, &pending));
  EXPECT_EQ(pending, 0);
  facesr_frame_stats st{};
  st.struct_size = sizeof st;
  ASSERT_OK(facesr_get_frame_stats(c, &st));
  EXPECT_EQ(st.frame, -1);
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_remove_spring(c, id));  // springs are gone
  // Controls cleared and the simulation restarted: the next frame is a fresh context's first.
  ASSERT_OK(facesr_step(c));
  ASSERT_OK(facesr_step(fresh));
  EXPECT_EQ(positions(c), positions(fresh));
  ASSERT_OK(facesr_get_frame_stats(c, &st));
  EXPECT_EQ(st.frame, 0);
}

TEST_F(Capi, BlendshapeNamesAndIndicesRoundTrip) {
  ASSERT_GT(info_.num_blendshapes, 0);
  for (int32_t i = 0; i < info_.num_blendshapes; ++i) {
    char buf[128];
    int32_t len = -1, back = -1;
    ASSERT_OK(facesr_rig_blendshape_name(rig_, i, buf, sizeof buf, &len));
    EXPECT_EQ(len, int32_t(std::strlen(buf)));
    ASSERT_OK(facesr_rig_blendshape_index(rig_, buf, &back));
    EXPECT_EQ(back, i) << buf;
  }
  const int32_t jaw = index("jawOpen");
  char small[5];
  std::memset(small, 'x', sizeof small);
  int32_t len = -1;
  ASSERT_OK(facesr_rig_blendshape_name(rig_, jaw, small, 4, &len));
  EXPECT_STREQ(small, "jaw");
  EXPECT_EQ(small[4], 'x') << "nothing past buf_size";
  EXPECT_EQ(len, 7);
  ASSERT_OK(facesr_rig_blendshape_name(rig_, jaw, small, 1, nullptr));
  EXPECT_STREQ(small, "");
  len = -1;
  ASSERT_OK(facesr_rig_blendshape_name(rig_, jaw, nullptr, 0, &len));  // length query
  EXPECT_EQ(len, 7);
  char exact[8];
  ASSERT_OK(facesr_rig_blendshape_name(rig_, jaw, exact, sizeof exact, &len));
  EXPECT_STREQ(exact, "jawOpen");
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_blendshape_name(rig_, jaw, small, -1, &len));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_blendshape_name(rig_, -1, small, 4, &len));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_blendshape_name(rig_, info_.num_blendshapes, small, 4, &len));
  int32_t i = 123;
  EXPECT_STATUS(FACESR_ERROR_NOT_FOUND, facesr_rig_blendshape_index(rig_, "jawopen", &i));
  EXPECT_STATUS(FACESR_ERROR_NOT_FOUND, facesr_rig_blendshape_index(rig_, "", &i));
  EXPECT_EQ(i, 123);
}

TEST_F(Capi, RigInfoGivesTheJawHinge) {
  const facesr::Rig r = facesr::load_rig(files().rig);
  for (int c = 0; c < 3; ++c) {
    EXPECT_FLOAT_EQ(info_.jaw_pivot[c], float(r.jaw.pivot[c]));
    EXPECT_FLOAT_EQ(info_.jaw_axis[c], float(r.jaw.axis[c]));
  }
  EXPECT_EQ(info_.checksum, facesr::rig_checksum(r));
}

TEST_F(Capi, SurfaceNormalsAndGeometry) {
  facesr_context* c = context();
  ASSERT_NE(c, nullptr);
  ASSERT_OK(facesr_set_weight_by_name(c, "jawOpen", 0.6f));
  ASSERT_OK(facesr_step(c));
  std::vector<float> n(static_cast<size_t>(n_));
  ASSERT_OK(facesr_get_normals(c, n.data(), n_));
  for (int32_t v = 0; v < info_.num_surface_vertices; ++v) {
    const double len = std::sqrt(n[size_t(3 * v)] * n[size_t(3 * v)] + n[size_t(3 * v + 1)] * n[size_t(3 * v + 1)] +
                                 n[size_t(3 * v + 2)] * n[size_t(3 * v + 2)]);
    ASSERT_NEAR(len, 1.0, 1e-4) << "vertex " << v;
  }
  std::vector<int32_t> tris(3 * size_t(info_.num_surface_triangles));
  ASSERT_OK(facesr_rig_get_triangles(rig_, tris.data(), int64_t(tris.size())));
  for (int32_t t : tris) ASSERT_TRUE(t >= 0 && t < info_.num_surface_vertices);
  const std::vector<float> p = positions(c), e = embedded(c);
  EXPECT_NE(p, e) << "the super-resolved surface differs from the embedded one";
  EXPECT_LT(max_diff(p, e), 5.0) << "but not wildly (cm)";
}

}  // namespace
