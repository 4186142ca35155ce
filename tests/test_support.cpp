#include "test_support.h"

#include <unistd.h>

#include <cstdlib>
#include <filesystem>

#include "rig/rig_io.h"
#include "rig/rig_preset.h"

namespace facesr::fixtures {

RigBuildOptions coarse_rig_options() {
  RigBuildOptions o;
  o.source = "procedural";
  apply_rig_preset(o, "coarse");  // the CLI's --preset coarse: the tests' rig is the one `rig build` makes
  o.verbose = false;
  return o;
}

const Rig& procedural_rig() {
  // Built once per test binary build (rig builds are deterministic), then
  // loaded by every test process: the build is ~4 s and ctest starts over a
  // hundred processes that use it.
  static const Rig rig = [] {
    const std::string dir = shared_cache_dir("procedural_coarse_rig", [](const std::string& d) {
      std::filesystem::create_directories(d);
      save_rig(build_rig(coarse_rig_options()), d + "/coarse.rig");
    });
    return load_rig(dir + "/coarse.rig");
  }();
  return rig;
}

double face_size(const Rig& r) {
  return (r.surface.colwise().maxCoeff() - r.surface.colwise().minCoeff()).norm();
}

int time_scale() {
  const char* env = std::getenv("FACESR_TEST_TIME_SCALE");
  const int s = env ? std::atoi(env) : 1;
  return s >= 1 ? s : 1;
}

std::string ict_dir() {
  const char* env = std::getenv("FACESR_ICT_DIR");
  return env ? env : FACESR_TEST_ICT_DIR;
}

std::string shared_cache_dir(const std::string& name, void (*make)(const std::string& dir)) {
  namespace fs = std::filesystem;
  const auto stamp = fs::last_write_time("/proc/self/exe").time_since_epoch().count();
  const fs::path root = fs::temp_directory_path() / ("facesr_test_cache_" + std::to_string(stamp));
  const fs::path dir = root / name;
  if (fs::is_directory(dir)) return dir.string();
  fs::create_directories(root);
  const fs::path tmp = root / (name + ".tmp" + std::to_string(::getpid()));
  fs::remove_all(tmp);
  make(tmp.string());
  std::error_code ec;
  fs::rename(tmp, dir, ec);  // fails harmlessly if another process got there first
  if (ec) fs::remove_all(tmp);
  return dir.string();
}

bool have_ict() { return std::filesystem::exists(ict_dir() + "/README.md") || std::filesystem::is_directory(ict_dir()); }

}  // namespace facesr::fixtures

#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace facesr::fixtures {

std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

CliResult run_cli(const std::string& args, const std::string& scratch_dir) {
  const std::string out = scratch_dir + "/cli_stdout.txt", err = scratch_dir + "/cli_stderr.txt";
  const std::string cmd = shell_quote(FACESR_CLI) + " " + args + " >" + shell_quote(out) + " 2>" + shell_quote(err);
  const int raw = std::system(cmd.c_str());
  CliResult r;
  r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
  r.out = read_text(out);
  r.err = read_text(err);
  return r;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace facesr::fixtures
