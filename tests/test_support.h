#pragma once
// Shared fixtures: the coarse procedural rig (built once per test binary) and
// the location of the ICT FaceKit data.
#include <gtest/gtest.h>

#include <exception>
#include <string>

#include "core/error.h"

#include "rig/rig.h"
#include "rig/rig_build.h"

namespace facesr::fixtures {

RigBuildOptions coarse_rig_options();
const Rig& procedural_rig();  // coarse preset; built once per build of the test binary (shared_cache_dir), loaded on first use
double face_size(const Rig& r);
std::string ict_dir();  // $FACESR_ICT_DIR or ../shared/data/ict-facekit
// How much slower than a Release build this test binary runs
// ($FACESR_TEST_TIME_SCALE, default 1; scripts/sanitize.sh sets 4): tests
// that wait for a process to reach a point scale their waits by it.
int time_scale();
bool have_ict();

// A folder made once per build of the test binary and shared by all its
// processes (ctest runs every test in a process of its own, so a suite's
// SetUpTestSuite would otherwise redo the work for each test). `make` fills
// a fresh temporary folder that is then renamed into place; concurrent
// makers race benignly. Keyed by the binary's modification time, so a
// rebuild never sees an older build's folder.
std::string shared_cache_dir(const std::string& name, void (*make)(const std::string& dir));

}  // namespace facesr::fixtures

namespace facesr::fixtures {

struct CliResult {
  int status = -1;
  std::string out, err;
};
// Runs the facesr binary with `args` (already shell-quoted where needed),
// capturing stdout and stderr through files in `scratch_dir`.
CliResult run_cli(const std::string& args, const std::string& scratch_dir);
std::string shell_quote(const std::string& s);
// The whole file as bytes ("" when it cannot be read).
std::string read_text(const std::string& path);

}  // namespace facesr::fixtures

namespace facesr::fixtures {

// Runs f and returns the facesr::Error message (fails the test if none thrown).
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "expected facesr::Error, got std::exception: " << e.what();
    return {};
  }
  ADD_FAILURE() << "expected facesr::Error, nothing thrown";
  return {};
}

}  // namespace facesr::fixtures

#include <unistd.h>

#include <filesystem>

#include "rig/rig_io.h"

namespace facesr::fixtures {

// A test suite with its own scratch folder (removed afterwards) holding the
// coarse procedural rig as "p.rig", and helpers to run the CLI in it.
// Derived suites name their folder with `static constexpr const char* kScratch`.
template <class Derived>
class ScratchSuite : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = std::filesystem::temp_directory_path() / (std::string(Derived::kScratch) + std::to_string(::getpid()));
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    save_rig(procedural_rig(), path("p.rig"));
  }
  static void TearDownTestSuite() { std::filesystem::remove_all(dir_); }
  static std::string path(const std::string& name) { return (dir_ / name).string(); }
  static std::string q(const std::string& name) { return shell_quote(path(name)); }
  static CliResult run(const std::string& args) { return run_cli(args, dir_.string()); }
  static inline std::filesystem::path dir_;
};

}  // namespace facesr::fixtures
