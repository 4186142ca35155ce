// Progress's ETA comes from this run's rate: work skipped mid-run (a resumed
// job's finished part) counts toward done but not toward the rate.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <thread>

#include "core/progress.h"

using namespace facesr;

namespace {

// elapsed and ETA of the last line printed.
std::pair<double, double> last_times(const std::string& out) {
  const size_t at = out.rfind("elapsed ");
  double elapsed = -1, eta = -1;
  if (at != std::string::npos) std::sscanf(out.c_str() + at, "elapsed %lfs ETA %lfs", &elapsed, &eta);
  return {elapsed, eta};
}

}  // namespace

TEST(CoreProgress, SkippedWorkDoesNotShortenTheEta) {
  testing::internal::CaptureStderr();
  Progress p("job", 100, true);
  p.skip(50);
  p.update(50, "half was already done");
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // past the print rate limit (0.5 s)
  p.update(60, "ten done in this run");
  const std::string out = testing::internal::GetCapturedStderr();
  EXPECT_NE(out.find("60/100"), std::string::npos) << out;
  const auto [elapsed, eta] = last_times(out);
  ASSERT_GT(elapsed, 0.5) << out;
  // 40 left at 10 per `elapsed`: 4 × elapsed (counting the skipped 50 as this
  // run's work would give 2/3 × elapsed).
  EXPECT_NEAR(eta, 4 * elapsed, 0.3) << out;  // both printed to 0.1 s
}
