// evaluate() on the procedural rig with synthetic methods whose errors are
// known: exact, a constant bias, per-vertex noise and a smooth sag. Checks the
// ordering and values of every metric, the report's keys, the files, and that
// bad input is an Error naming the method and frame, with nothing written.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "eval/evaluate.h"
#include "test_support.h"

namespace fs = std::filesystem;
using namespace facesr;
using facesr::fixtures::error_of;

namespace {

constexpr int kFrames = 6;

// Test frames: two "sequences" of a smooth, frame-varying deformation.
std::vector<EvalFrame> test_frames(const Rig& rig) {
  std::vector<EvalFrame> frames;
  Vec3 lo, hi;
  bounding_box(rig.surface, lo, hi);
  for (int f = 0; f < kFrames; ++f) {
    EvalFrame fr;
    fr.sequence = f < 4 ? "anger" : "fear";
    fr.frame = f < 4 ? f : f - 4;
    for (long v = 0; v < rig.surface.rows(); ++v) {
      const double y = (rig.surface(v, 1) - lo.y()) / (hi.y() - lo.y());
      fr.reference_disp.push_back(0);
      fr.reference_disp.push_back(float(-0.3 * (f + 1) * (1 - y) * (1 - y)));  // jaw-like drop
      fr.reference_disp.push_back(float(0.05 * f * y));
    }
    frames.push_back(std::move(fr));
  }
  return frames;
}

EvalMethod offset(const std::string& name, const std::vector<EvalFrame>& frames, float dx, float dy, float dz) {
  EvalMethod m{name, {}};
  for (const EvalFrame& f : frames) {
    std::vector<float> p = f.reference_disp;
    for (size_t i = 0; i < p.size(); i += 3) {
      p[i] += dx;
      p[i + 1] += dy;
      p[i + 2] += dz;
    }
    m.predicted_disp.push_back(std::move(p));
  }
  return m;
}

EvalMethod noisy(const std::string& name, const std::vector<EvalFrame>& frames, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<float> g(0, float(sigma));
  EvalMethod m{name, {}};
  for (const EvalFrame& f : frames) {
    std::vector<float> p = f.reference_disp;
    for (float& x : p) x += g(rng);
    m.predicted_disp.push_back(std::move(p));
  }
  return m;
}

// A smooth under-shoot: the reference's deformation at 80 %.
EvalMethod damped(const std::string& name, const std::vector<EvalFrame>& frames) {
  EvalMethod m{name, {}};
  for (const EvalFrame& f : frames) {
    std::vector<float> p = f.reference_disp;
    for (float& x : p) x *= 0.8f;
    m.predicted_disp.push_back(std::move(p));
  }
  return m;
}

const SpectralBasis& basis() {
  static const SpectralBasis b = [] {
    const Rig& rig = fixtures::procedural_rig();
    return spectral_basis(rig.surface, rig.surface_tris, {40});
  }();
  return b;
}

class EvalEvaluate : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("facesr_eval_evaluate_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& n) const { return (dir_ / n).string(); }
  EvalOptions outputs() const {
    EvalOptions o;
    o.basis = &basis();
    o.csv_path = path("frames.csv");
    o.svg_path = path("frames.svg");
    o.picture_dir = path("pictures");
    o.picture_frames = {1, 5};
    o.tile_width = 160;
    return o;
  }
  fs::path dir_;
};

}  // namespace

TEST_F(EvalEvaluate, SyntheticMethodsComeOutInTheirKnownOrder) {
  const Rig& rig = fixtures::procedural_rig();
  const auto frames = test_frames(rig);
  // Exact; a 0.1 cm translation; per-coordinate noise of 0.1 cm; an 80 % under-shoot.
  const std::vector<EvalMethod> methods = {offset("ours", frames, 0, 0, 0), offset("embedded", frames, 0.06f, 0, 0.08f),
                                           noisy("rbf", frames, 0.1, 3), damped("mls", frames)};
  const EvalReport r = evaluate(rig, frames, methods, outputs());
  ASSERT_EQ(r.methods.size(), 4u);
  const MethodReport &ours = *r.method("ours"), &emb = *r.method("embedded"), &rbf = *r.method("rbf"),
                     &mls = *r.method("mls");

  // Exact: zero everywhere.
  EXPECT_EQ(ours.vertex_cm.max, 0);
  EXPECT_EQ(ours.dame, 0);
  EXPECT_EQ(ours.normal_deg, 0);
  EXPECT_EQ(ours.normalized.max, 0);
  // Translation by (0.06, 0, 0.08): every vertex 0.1 cm off, and no shape error.
  EXPECT_NEAR(emb.vertex_cm.mean, 0.1, 1e-6);
  EXPECT_NEAR(emb.vertex_cm.median, 0.1, 1e-6);
  EXPECT_NEAR(emb.vertex_cm.min, 0.1, 1e-6);
  EXPECT_NEAR(emb.vertex_cm.max, 0.1, 1e-6);
  EXPECT_LT(emb.vertex_cm.std, 1e-6);
  EXPECT_LT(emb.dame, 1e-5);
  EXPECT_LT(emb.normal_deg, 1e-3);
  EXPECT_NEAR(emb.bands.low_fraction, 1, 1e-6);
  EXPECT_NEAR(emb.bands.low_rms_cm, 0.1, 1e-5);
  // Noise: |N(0, 0.1 I3)| has mean 0.1 * 2 sqrt(2 / pi) = 0.1596 cm; it bends
  // every edge, so the largest DAME and normal error, and mostly high band.
  EXPECT_NEAR(rbf.vertex_cm.mean, 0.1596, 0.01);
  EXPECT_GT(rbf.dame, 10 * mls.dame);
  EXPECT_GT(rbf.normal_deg, mls.normal_deg);
  EXPECT_GT(rbf.bands.high_fraction, 0.85);
  // The smooth under-shoot's error is the reference deformation's 20 %: low band.
  EXPECT_GT(mls.bands.low_fraction, 0.95);
  EXPECT_GT(mls.dame, 0);
  for (const MethodReport* m : {&ours, &emb, &rbf, &mls})
    if (m->bands.total_energy() > 0) EXPECT_NEAR(m->bands.low_fraction + m->bands.high_fraction, 1, 1e-12);

  // Ordering by mean error, and the table 1 normalisation over all of them.
  EXPECT_LT(ours.vertex_cm.mean, emb.vertex_cm.mean);
  EXPECT_LT(emb.vertex_cm.mean, rbf.vertex_cm.mean);
  double largest = 0;
  for (const MethodReport& m : r.methods)
    for (const double x : m.frame_mean_cm) largest = std::max(largest, x);
  EXPECT_DOUBLE_EQ(r.normalizer_cm, largest);
  double top = 0;
  for (const MethodReport& m : r.methods) top = std::max(top, m.normalized.max);
  EXPECT_DOUBLE_EQ(top, 1.0);
  EXPECT_NEAR(emb.normalized.mean, emb.frame_cm.mean / largest, 1e-12);
  EXPECT_EQ(r.frames_ours_beats_embedded, kFrames);

  // Files: CSV rows, one polyline per method, one picture per chosen frame.
  std::ifstream csv(path("frames.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "sequence,frame,ours_mean_cm,embedded_mean_cm,rbf_mean_cm,mls_mean_cm");
  int rows = 0;
  for (std::string l; std::getline(csv, l);) ++rows;
  EXPECT_EQ(rows, kFrames);
  std::ifstream svg_in(path("frames.svg"));
  const std::string svg((std::istreambuf_iterator<char>(svg_in)), std::istreambuf_iterator<char>());
  size_t polylines = 0;
  for (size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++polylines;
  EXPECT_EQ(polylines, methods.size());
  ASSERT_EQ(r.pictures.size(), 2u);
  EXPECT_EQ(fs::path(r.pictures[0]).filename(), "error_anger_1.png");
  EXPECT_EQ(fs::path(r.pictures[1]).filename(), "error_fear_1.png");
  for (const std::string& p : r.pictures) EXPECT_GT(fs::file_size(p), 1000u);
  EXPECT_GT(r.heat_scale_cm, 0.1);  // the noise's largest vertex error
}

TEST_F(EvalEvaluate, JsonHasTheAgreedKeysAndMarkdownOneRowPerMethod) {
  const Rig& rig = fixtures::procedural_rig();
  const auto frames = test_frames(rig);
  EvalOptions o;
  o.basis = &basis();
  const EvalReport r = evaluate(
      rig, frames,
      {offset("ours", frames, 0.01f, 0, 0), offset("embedded", frames, 0, 0.05f, 0), noisy("vae", frames, 0.02, 5)}, o);
  const nlohmann::json j = r.to_json();
  EXPECT_EQ(j.at("units"), "cm");
  EXPECT_EQ(j.at("test_frames"), kFrames);
  EXPECT_EQ(j.at("frames_ours_beats_embedded"), kFrames);
  for (const char* name : {"ours", "embedded", "vae"}) {
    const auto& m = j.at(name);
    for (const char* k : {"mean_cm", "median_cm", "std_cm", "max_cm", "min_cm", "dame", "normal_deg",
                          "low_band_fraction", "high_band_fraction", "low_band_rms_cm", "high_band_rms_cm"})
      EXPECT_TRUE(m.at(k).is_number()) << name << "." << k;
    for (const char* k : {"mean", "median", "std", "max", "min"}) {
      EXPECT_TRUE(m.at("normalized").at(k).is_number()) << name << ".normalized." << k;
      EXPECT_TRUE(m.at("frame_mean_cm").at(k).is_number());
    }
  }
  EXPECT_NEAR(j.at("ours").at("mean_cm").get<double>(), 0.01, 1e-6);
  EXPECT_EQ(j.at("eval").at("methods"), nlohmann::json({"ours", "embedded", "vae"}));
  EXPECT_EQ(j.at("eval").at("spectral").at("k"), 40);
  EXPECT_EQ(j.at("eval").at("dame_units"), "rad");

  const std::string md = r.to_markdown();
  EXPECT_NE(md.find("| ours | "), std::string::npos);
  EXPECT_NE(md.find("| embedded | "), std::string::npos);
  EXPECT_NE(md.find("| vae | "), std::string::npos);
  EXPECT_NE(md.find("DAME"), std::string::npos);
  EXPECT_NE(md.find(" cm"), std::string::npos);
  // Header, separator, three rows: every table line has the same number of cells.
  std::istringstream lines(md);
  std::string l;
  std::vector<size_t> bars;
  while (std::getline(lines, l) && !l.empty()) bars.push_back(size_t(std::count(l.begin(), l.end(), '|')));
  ASSERT_EQ(bars.size(), 5u);
  for (const size_t b : bars) EXPECT_EQ(b, bars[0]);
}

TEST_F(EvalEvaluate, WithoutOursAndEmbeddedThereIsNoBeatsCountAndAnyNameWorks) {
  const Rig& rig = fixtures::procedural_rig();
  const auto frames = test_frames(rig);
  EvalOptions o;
  o.spectral = false;
  const EvalReport r = evaluate(rig, frames, {offset("my method (v2), α", frames, 0, 0, 0.2f)}, o);
  const nlohmann::json j = r.to_json();
  EXPECT_FALSE(j.contains("frames_ours_beats_embedded"));
  EXPECT_FALSE(j.at("my method (v2), α").contains("low_band_fraction"));
  EXPECT_NEAR(j.at("my method (v2), α").at("normalized").at("max").get<double>(), 1, 1e-12);
}

TEST_F(EvalEvaluate, BadInputIsAnErrorNamingTheProblemAndWritesNothing) {
  const Rig& rig = fixtures::procedural_rig();
  const auto frames = test_frames(rig);
  const EvalOptions o = outputs();
  const EvalMethod good = offset("ours", frames, 0, 0, 0);
  auto expect_error = [&](const std::vector<EvalFrame>& fr, const std::vector<EvalMethod>& ms,
                          const std::string& needle, const EvalOptions& opt) {
    const std::string msg = error_of([&] { evaluate(rig, fr, ms, opt); });
    EXPECT_NE(msg.find(needle), std::string::npos) << msg;
    EXPECT_TRUE(fs::is_empty(dir_)) << "after: " << msg;
  };

  expect_error(frames, {}, "no methods", o);
  expect_error({}, {good}, "no test frames", o);

  EvalMethod short_frame = offset("rbf", frames, 0, 0, 0);
  short_frame.predicted_disp[3].resize(30);
  expect_error(frames, {good, short_frame}, "method 'rbf', test frame 3 ('anger' #3): 30 floats", o);

  EvalMethod nan = offset("mls", frames, 0, 0, 0);
  nan.predicted_disp[4][3 * 17 + 1] = std::nanf("");
  expect_error(frames, {good, nan}, "method 'mls', test frame 4 ('fear' #0): vertex 17 has a non-finite", o);

  EvalMethod missing = good;
  missing.name = "vae";
  missing.predicted_disp.pop_back();
  expect_error(frames, {good, missing}, "method 'vae' has 5 predicted frames for 6 test frames", o);

  expect_error(frames, {good, good}, "'ours' is given twice", o);
  expect_error(frames, {offset("units", frames, 0, 0, 0)}, "name of a report key", o);
  expect_error(frames, {offset("", frames, 0, 0, 0)}, "empty name", o);

  auto bad_ref = frames;
  bad_ref[2].reference_disp.pop_back();
  expect_error(bad_ref, {good}, "test frame 2 ('anger' #2), reference displacement", o);

  EvalOptions far = o;
  far.picture_frames = {0, 6};
  expect_error(frames, {good}, "picture frame 6", far);

  EvalOptions nowhere = o;
  nowhere.csv_path = path("missing/folder/frames.csv");
  expect_error(frames, {good}, "does not exist", nowhere);

  SpectralBasis other = basis();
  other.mass.resize(10);
  EvalOptions wrong_basis = o;
  wrong_basis.basis = &other;
  expect_error(frames, {good}, "spectral basis has 10 vertices", wrong_basis);
}
