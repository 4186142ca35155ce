// Benchmark reports: machine tags that tell CPUs apart, and Markdown sections
// that a run replaces without touching the rest of the file.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>

#include <unistd.h>

#include "bench/bench_report.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;

using fixtures::read_text;

TEST(BenchReport, MachineSlugIsATagWordWithTheCpuFamilyAndModel) {
  const std::string slug = machine_slug();
  EXPECT_TRUE(std::regex_match(slug, std::regex("[a-z0-9]+(-[a-z0-9]+)*"))) << slug;
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  bool has_family = false;
  while (std::getline(cpuinfo, line) && !line.empty()) has_family = has_family || line.rfind("cpu family", 0) == 0;
  if (!has_family) GTEST_SKIP() << "/proc/cpuinfo has no 'cpu family' line on this machine";
  EXPECT_TRUE(std::regex_search(slug, std::regex("-family-[0-9]+-model-[0-9]+$"))) << slug;
  EXPECT_TRUE(std::regex_search(machine_description(), std::regex("\\(family [0-9]+, model [0-9]+\\), [0-9]+ cores$")))
      << machine_description();
}

TEST(BenchReport, SectionsAreReplacedInPlaceAndAppendedWhenNew) {
  const fs::path dir = fs::temp_directory_path() / ("facesr_bench_report_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path md = dir / "B.md";
  { std::ofstream(md) << "# Head\n\n<!-- a:start -->\nold a\n<!-- a:end -->\n\ntail\n"; }
  update_markdown_section(md.string(), "a", "new a");
  update_markdown_section(md.string(), "b", "new b\n");
  EXPECT_EQ(read_text(md), "# Head\n\n<!-- a:start -->\nnew a\n<!-- a:end -->\n\ntail\n\n<!-- b:start -->\nnew b\n<!-- b:end -->\n");
  { std::ofstream(md) << "<!-- a:start -->\nno end\n"; }
  EXPECT_THROW(update_markdown_section(md.string(), "a", "x"), std::exception);
  EXPECT_EQ(read_text(md), "<!-- a:start -->\nno end\n");
  fs::remove_all(dir);
}
