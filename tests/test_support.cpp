#include "test_support.h"

#include <cstdlib>
#include <filesystem>

namespace facesr::fixtures {

RigBuildOptions coarse_rig_options() {
  RigBuildOptions o;
  o.source = "procedural";
  o.procedural.grid_h = 0.25;
  o.procedural.edge = 0.8;
  o.flesh_grid_h = 0.3;
  o.bone_edge = 0.8;
  o.hr_max_volume = 0.15;
  o.lr_cell = 1.2;
  o.min_hr_over_lr = 0;
  o.verbose = false;
  return o;
}

const Rig& procedural_rig() {
  static const Rig rig = build_rig(coarse_rig_options());
  return rig;
}

double face_size(const Rig& r) {
  return (r.surface.colwise().maxCoeff() - r.surface.colwise().minCoeff()).norm();
}

std::string ict_dir() {
  const char* env = std::getenv("FACESR_ICT_DIR");
  return env ? env : FACESR_TEST_ICT_DIR;
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
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

}  // namespace facesr::fixtures
