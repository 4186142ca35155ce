// The fuzz targets (tests/fuzz) outside libFuzzer: every seed file the
// project writes is accepted, every truncation of a binary seed and a sweep
// of byte edits are rejected with a facesr::Error (never another exception or
// a crash), and every input fuzzing once broke, kept under
// tests/fuzz/regressions/<target>/, is handled.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "core/binary_io.h"
#include "fuzz_targets.h"
#include "tiny_files.h"

namespace fs = std::filesystem;
using namespace facesr;
using facesr::fuzz::Outcome;

namespace {

const char* kBinary[] = {"rig", "model", "sequence", "dataset"};

bool is_binary(const std::string& t) {
  for (const char* b : kBinary)
    if (t == b) return true;
  return false;
}

std::string livelink_dir() {
  const char* env = std::getenv("FACESR_LIVELINK_DIR");
  return env ? env : std::string(FACESR_TEST_SOURCE_DIR) + "/../shared/data/livelink";
}

class FuzzTargets : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new fs::path(fs::temp_directory_path() / ("facesr_fuzz_seeds_" + std::to_string(::getpid())));
    tiny::write_seed_files(dir_->string(), livelink_dir());
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }
  static std::vector<fs::path> seeds(const std::string& target) {
    std::vector<fs::path> out;
    if (fs::is_directory(*dir_ / target))
      for (const auto& e : fs::directory_iterator(*dir_ / target)) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
  }
  static Outcome run(const fuzz::Target& t, const std::vector<uint8_t>& b) { return t.run(b.data(), b.size()); }
  static fs::path* dir_;
};
fs::path* FuzzTargets::dir_ = nullptr;

TEST_F(FuzzTargets, EverySeedIsAccepted) {
  for (const auto& t : fuzz::targets()) {
    const auto files = seeds(t.name);
    EXPECT_FALSE(files.empty()) << t.name << " has no seed files";
    for (const auto& f : files) EXPECT_EQ(run(t, read_file_bytes(f.string())), Outcome::Accepted) << f;
  }
}

TEST_F(FuzzTargets, EveryTruncationOfABinarySeedIsRejected) {
  for (const char* name : kBinary) {
    const auto& t = *fuzz::find_target(name);
    for (const auto& f : seeds(name)) {
      const auto b = read_file_bytes(f.string());
      // Every length up to 512 bytes, then every 61st (a cut anywhere in the
      // payload): the raw file fails its size checks, the resealed one a
      // parser's bounds checks.
      for (size_t n = 0; n < b.size(); n += n < 512 ? 1 : 61) {
        const std::vector<uint8_t> cut(b.begin(), b.begin() + long(n));
        EXPECT_EQ(run(t, cut), Outcome::Rejected) << f << " cut to " << n << " bytes";
      }
    }
  }
}

// Each byte of each seed set to 0x00, 0xff and 0x80 in turn: whatever the
// loader decides, it decides with an Error or a valid result.
TEST_F(FuzzTargets, ByteEditsGiveAnErrorOrAValidResult) {
  for (const auto& t : fuzz::targets()) {
    for (const auto& f : seeds(t.name)) {
      const auto b = read_file_bytes(f.string());
      const size_t step = b.size() > 4000 ? b.size() / 4000 : 1;
      for (size_t i = 0; i < b.size(); i += step) {
        for (uint8_t v : {uint8_t(0x00), uint8_t(0xff), uint8_t(0x80)}) {
          auto e = b;
          e[i] = v;
          EXPECT_NO_THROW((void)run(t, e)) << f << " byte " << i << " = " << int(v);
        }
      }
    }
  }
}

TEST_F(FuzzTargets, RegressionInputsAreHandled) {
  const fs::path root = fs::path(FACESR_TEST_SOURCE_DIR) / "tests" / "fuzz" / "regressions";
  int n = 0;
  for (const auto& t : fuzz::targets()) {
    if (!fs::is_directory(root / t.name)) continue;
    for (const auto& e : fs::directory_iterator(root / t.name)) {
      if (e.path().filename() == "README.md") continue;
      ++n;
      EXPECT_NO_THROW((void)run(t, read_file_bytes(e.path().string()))) << e.path();
    }
  }
  for (const auto& e : fs::directory_iterator(root))
    if (e.is_directory()) EXPECT_NE(fuzz::find_target(e.path().filename().string()), nullptr) << e.path();
  std::cout << n << " regression inputs replayed\n";
}

// scripts/fuzz.sh builds the executables listed in tests/fuzz/CMakeLists.txt:
// the list must be the targets here, so no loader goes unfuzzed.
TEST(FuzzTargetList, TheFuzzBuildMakesEveryTarget) {
  std::ifstream in(std::string(FACESR_TEST_SOURCE_DIR) + "/tests/fuzz/CMakeLists.txt");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::smatch m;
  ASSERT_TRUE(std::regex_search(text, m, std::regex(R"(foreach\(t ([a-z_ ]+)\))")));
  std::set<std::string> built;
  std::istringstream names(m[1].str());
  for (std::string s; names >> s;) built.insert(s);
  std::set<std::string> declared;
  for (const auto& t : fuzz::targets()) declared.insert(t.name);
  EXPECT_EQ(built, declared);
}

TEST(FuzzReseal, MakesSizeAndChecksumMatchSoOnlyTheEditRemains) {
  const auto dir = fs::temp_directory_path() / ("facesr_fuzz_reseal_" + std::to_string(::getpid()));
  tiny::write_seed_files(dir.string());
  auto rig = read_file_bytes((dir / "rig" / "tiny.rig").string());
  EXPECT_EQ(fuzz::reseal_rig(rig.data(), rig.size()), rig);  // already sealed
  rig.insert(rig.end() - 8, 3, uint8_t(0));                   // 3 bytes more payload
  const auto sealed = fuzz::reseal_rig(rig.data(), rig.size());
  uint64_t payload;
  std::memcpy(&payload, sealed.data() + 16, 8);
  EXPECT_EQ(payload, sealed.size() - 32);
  auto fsm = read_file_bytes((dir / "model" / "plain.fsm").string());
  EXPECT_EQ(fuzz::reseal_trailing_checksum(fsm.data(), fsm.size()), fsm);
  fsm[20] ^= 1;
  EXPECT_NE(fuzz::reseal_trailing_checksum(fsm.data(), fsm.size()), fsm);
  fs::remove_all(dir);
}

}  // namespace
