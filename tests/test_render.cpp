// Software rendering of simulated sequences: z-buffered rasterization, PNG
// grids of frames (size, motion visible, heat colouring), validation, glTF.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "core/error.h"
#include "perf/sequence_io.h"
#include "render/mesh_raster.h"
#include "render/sequence_gltf.h"
#include "render/sequence_render.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace fs = std::filesystem;
using namespace facesr;

namespace {

constexpr int kGrid = 24;  // vertices per side of the test face

// A 6 x 6 cm dome facing +z: enough to shade, small enough to render in milliseconds.
Rig dome_rig() {
  Rig rig;
  rig.name = "dome";
  const int n = kGrid;
  rig.surface.resize(n * n, 3);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double x = -3 + 6.0 * i / (n - 1), y = -3 + 6.0 * j / (n - 1);
      rig.surface.row(j * n + i) << x, y, 2 * std::exp(-(x * x + y * y) / 6);
    }
  rig.surface_tris.resize(2 * (n - 1) * (n - 1), 3);
  for (int j = 0, f = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const int a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      rig.surface_tris.row(f++) << a, b, d;
      rig.surface_tris.row(f++) << a, d, c;
    }
  return rig;
}

// Frame f: the dome's right half slides down by 0.3 f cm and the top bulges.
Sequence dome_sequence(const Rig& rig, int frames) {
  Sequence s;
  const int S = rig.num_surface_vertices();
  s.header.num_surface = S;
  s.header.fps = 30;
  for (int f = 0; f < frames; ++f) {
    s.time.push_back(f / 30.0);
    for (int v = 0; v < S; ++v) {
      const double x = rig.surface(v, 0), y = rig.surface(v, 1), z = rig.surface(v, 2);
      const double slide = x > 0 ? 0.3 * f * x / 3 : 0;
      s.surface.push_back(float(x));
      s.surface.push_back(float(y - slide));
      s.surface.push_back(float(z + 0.2 * f * std::max(0.0, y) / 3));
    }
  }
  s.header.num_frames = frames;
  return s;
}

struct Decoded {
  int w = 0, h = 0;
  std::vector<uint8_t> rgb;
  Rgb at(int x, int y) const {
    const uint8_t* p = &rgb[(size_t(y) * w + x) * 3];
    return {p[0], p[1], p[2]};
  }
};

Decoded decode_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_TRUE(bytes.size() >= 8 && std::equal(signature, signature + 8, bytes.begin())) << path;
  Decoded d;
  int channels = 0;
  uint8_t* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &d.w, &d.h, &channels, 3);
  EXPECT_NE(px, nullptr) << path;
  if (px) {
    d.rgb.assign(px, px + size_t(d.w) * d.h * 3);
    stbi_image_free(px);
  }
  return d;
}

bool same(Rgb a, Rgb b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected facesr::Error";
  return {};
}

#define EXPECT_HAS(msg, text) EXPECT_NE((msg).find(text), std::string::npos) << (msg)

class Render : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = fs::temp_directory_path() / ("facesr_render_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  static void TearDownTestSuite() { fs::remove_all(dir_); }
  static fs::path dir_;
};
fs::path Render::dir_;

}  // namespace

TEST(MeshRaster, DepthTestKeepsTheNearestSurface) {
  // Two overlapping quads; the near one (z = 1) is drawn first, the far one (z = -1) second.
  const float xyz[] = {-1, -1, 1, 1, -1, 1, 1, 1, 1, -1, 1, 1, -2, -2, -1, 2, -2, -1, 2, 2, -1, -2, 2, -1};
  Tris tris(4, 3);
  tris << 0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7;
  std::vector<Rgb> colour(8, Rgb{0, 200, 0});
  for (int v = 4; v < 8; ++v) colour[v] = Rgb{200, 0, 0};
  Image img(100, 100, Rgb{0, 0, 0});
  const FrontView view = frame_front_view(Vec3(-2, -2, -1), Vec3(2, 2, 1), 0, 0, 100, 100, 1.0);
  rasterize_mesh(img, view, xyz, 8, tris, colour, Rgb{});
  const Rgb centre = img.get(50, 50), corner = img.get(5, 5);
  EXPECT_GT(centre.g, 100);
  EXPECT_EQ(centre.r, 0);
  EXPECT_GT(corner.r, 100);  // only the far quad covers the corner
  EXPECT_EQ(corner.g, 0);
  // Lambert: a face turned away from the light (from above) is darker than one facing the camera.
  const float facing[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  const float tilted[] = {-1, -1, 0, 1, -1, 0, 1, 1, 2, -1, 1, 2};  // normal (0, -1, 1)/sqrt(2)
  Tris q(2, 3);
  q << 0, 1, 2, 0, 2, 3;
  Image lit(100, 100, Rgb{0, 0, 0}), dim(100, 100, Rgb{0, 0, 0});
  rasterize_mesh(lit, view, facing, 4, q, {}, Rgb{200, 200, 200});
  rasterize_mesh(dim, view, tilted, 4, q, {}, Rgb{200, 200, 200});
  EXPECT_GT(lit.get(50, 50).r, 150);
  EXPECT_LT(dim.get(50, 50).r, lit.get(50, 50).r - 40);
  EXPECT_GT(dim.get(50, 50).r, 40);  // ambient keeps it visible
  // Out-of-range indices are an Error, not a crash.
  Tris bad(1, 3);
  bad << 0, 1, 9;
  EXPECT_THROW(rasterize_mesh(img, view, xyz, 8, bad, {}, Rgb{}), Error);
}

TEST(SequenceRender, EvenlySpacedFrames) {
  EXPECT_EQ(evenly_spaced_frames(10, 4), (std::vector<int>{0, 3, 6, 9}));
  EXPECT_EQ(evenly_spaced_frames(3, 6), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(evenly_spaced_frames(1, 6), (std::vector<int>{0}));
  EXPECT_EQ(evenly_spaced_frames(100, 1), (std::vector<int>{0}));
  EXPECT_TRUE(evenly_spaced_frames(0, 3).empty());
}

TEST_F(Render, WritesPngGridOfTheExpectedSize) {
  const Rig rig = dome_rig();
  const Sequence seq = dome_sequence(rig, 5);
  RenderOptions opt;
  opt.tile_width = 200;
  opt.tile_height = 180;
  opt.columns = 2;
  const std::string path = (dir_ / "grid.png").string();
  const RenderSummary s = render_sequence_png(rig, seq, {0, 2, 4}, path, opt);
  const Decoded img = decode_png(path);
  EXPECT_EQ(img.w, 400);
  EXPECT_EQ(img.w, s.width);
  EXPECT_EQ(img.h, s.height);
  EXPECT_GT(img.h, 2 * 180);  // two rows plus a title strip
  EXPECT_LT(img.h, 2 * 180 + 40);
  // The face fills the middle of the first panel.
  const Rgb bg{120, 120, 120};
  EXPECT_FALSE(same(img.at(100, img.h - 2 * 180 + 100), bg));
  // Max displacement: the corner (3, -3) slides 0.3 * 4 cm at frame 4; (3, 3) also rises 0.8 cm.
  EXPECT_NEAR(s.max_displacement_cm, std::sqrt(1.2 * 1.2 + 0.8 * 0.8), 1e-5);
  // Automatic layout: a near-square grid, tile height from the face's aspect.
  const RenderSummary a = render_sequence_png(rig, seq, {0, 1, 2, 3}, path, RenderOptions{});
  EXPECT_EQ(a.width, 2 * 360);
  EXPECT_EQ(decode_png(path).h, a.height);
}

TEST_F(Render, DifferentSurfacesGiveDifferentPixels) {
  const Rig rig = dome_rig();
  const Sequence seq = dome_sequence(rig, 4);
  RenderOptions opt;
  opt.tile_width = 240;
  opt.tile_height = 240;
  const std::string p0 = (dir_ / "f0.png").string(), p3 = (dir_ / "f3.png").string(),
                    again = (dir_ / "f0b.png").string();
  render_sequence_png(rig, seq, {0}, p0, opt);
  render_sequence_png(rig, seq, {3}, p3, opt);
  render_sequence_png(rig, seq, {0}, again, opt);
  const Decoded a = decode_png(p0), b = decode_png(p3), c = decode_png(again);
  ASSERT_EQ(a.w, b.w);
  ASSERT_EQ(a.h, b.h);
  EXPECT_EQ(a.rgb, c.rgb) << "rendering is deterministic";
  // Compare the lower part of the panel only, below the labels.
  long differ = 0;
  for (int y = a.h / 3; y < a.h; ++y)
    for (int x = 0; x < a.w; ++x) differ += !same(a.at(x, y), b.at(x, y));
  EXPECT_GT(differ, 500) << "frame 3 moved the surface; the pictures must differ";
}

TEST_F(Render, HeatColoursDisplacementWithLegend) {
  const Rig rig = dome_rig();
  const Sequence seq = dome_sequence(rig, 4);
  RenderOptions opt;
  opt.tile_width = 240;
  opt.tile_height = 240;
  opt.columns = 2;
  const std::string plain = (dir_ / "plain.png").string(), heat = (dir_ / "heat.png").string();
  const RenderSummary sp = render_sequence_png(rig, seq, {0, 3}, plain, opt);
  opt.heat = true;
  const RenderSummary sh = render_sequence_png(rig, seq, {0, 3}, heat, opt);
  EXPECT_GT(sh.height, sp.height);  // legend strip
  EXPECT_EQ(sh.max_displacement_cm, sp.max_displacement_cm);
  const Decoded img = decode_png(heat);
  // Frame 0 (left panel) has no displacement: blue-ish skin, no red anywhere.
  // Frame 3 (right panel) has its largest displacement: some red.
  auto reddish = [](Rgb c) { return c.r > 120 && c.r > 2 * c.b && c.g < 120; };
  long red_left = 0, red_right = 0, blue_left = 0;
  for (int y = 40; y < sp.height; ++y)
    for (int x = 0; x < img.w; ++x) {
      const Rgb c = img.at(x, y);
      if (x < 240) {
        red_left += reddish(c);
        blue_left += c.b > c.r + 40;
      } else {
        red_right += reddish(c);
      }
    }
  EXPECT_EQ(red_left, 0);
  EXPECT_GT(blue_left, 1000);
  EXPECT_GT(red_right, 50);
  // The legend's colour bar runs from blue to red.
  bool legend_red = false;
  for (int y = sp.height; y < img.h; ++y)
    for (int x = 0; x < img.w; ++x) legend_red |= reddish(img.at(x, y));
  EXPECT_TRUE(legend_red);
  EXPECT_TRUE(same(heat_colour(0), Rgb{40, 60, 200}));
  EXPECT_TRUE(same(heat_colour(1), Rgb{220, 40, 30}));
}

TEST_F(Render, InvalidInputsAreErrorsAndWriteNothing) {
  const Rig rig = dome_rig();
  const Sequence seq = dome_sequence(rig, 3);
  const fs::path out = dir_ / "never.png";
  std::string msg = error_of([&] { render_sequence_png(rig, seq, {0, 3}, out.string()); });
  EXPECT_HAS(msg, "frame 3 is out of range");
  EXPECT_HAS(msg, "3 frames");
  msg = error_of([&] { render_sequence_png(rig, seq, {-1}, out.string()); });
  EXPECT_HAS(msg, "frame -1 is out of range");
  msg = error_of([&] { render_sequence_png(rig, seq, {}, out.string()); });
  EXPECT_HAS(msg, "no frames");
  RenderOptions tiny;
  tiny.tile_width = 10;
  msg = error_of([&] { render_sequence_png(rig, seq, {0}, out.string(), tiny); });
  EXPECT_HAS(msg, "tile width 10");
  RenderOptions huge;
  huge.tile_width = 4096;
  huge.columns = 8;
  msg = error_of([&] { render_sequence_png(rig, seq, std::vector<int>(8, 0), out.string(), huge); });
  EXPECT_HAS(msg, "more than 16384");
  Rig other = dome_rig();
  other.surface.conservativeResize(10, 3);
  msg = error_of([&] { render_sequence_png(other, seq, {0}, out.string()); });
  EXPECT_HAS(msg, "576 surface vertices");
  EXPECT_HAS(msg, "has 10");
  EXPECT_FALSE(fs::exists(out));
  for (const auto& e : fs::directory_iterator(dir_))
    EXPECT_EQ(e.path().filename().string().find("never.png"), std::string::npos) << e.path();
}

TEST_F(Render, GltfParsesBackWithMorphTargetsPerFrame) {
  const Rig rig = dome_rig();
  const Sequence seq = dome_sequence(rig, 4);
  const std::string path = (dir_ / "seq.gltf").string();
  write_sequence_gltf(rig, seq, path);
  std::ifstream in(path);
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["asset"]["extras"]["units"], "cm");
  EXPECT_EQ(j["nodes"][0]["scale"][0], 0.01);
  const auto& prim = j["meshes"][0]["primitives"][0];
  ASSERT_EQ(prim["targets"].size(), 3u);
  EXPECT_EQ(j["meshes"][0]["weights"].size(), 3u);

  // Decode the embedded buffer.
  const std::string uri = j["buffers"][0]["uri"];
  const std::string prefix = "data:application/octet-stream;base64,";
  ASSERT_EQ(uri.rfind(prefix, 0), 0u);
  std::vector<uint8_t> buf;
  {
    const std::string b64 = uri.substr(prefix.size());
    auto val = [](char c) -> int {
      if (c >= 'A' && c <= 'Z') return c - 'A';
      if (c >= 'a' && c <= 'z') return c - 'a' + 26;
      if (c >= '0' && c <= '9') return c - '0' + 52;
      return c == '+' ? 62 : c == '/' ? 63 : -1;
    };
    uint32_t acc = 0;
    int bits = 0;
    for (char c : b64) {
      if (c == '=') break;
      acc = (acc << 6) | uint32_t(val(c));
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        buf.push_back(uint8_t((acc >> bits) & 0xFF));
      }
    }
  }
  ASSERT_EQ(buf.size(), j["buffers"][0]["byteLength"].get<size_t>());
  auto floats = [&](int accessor) {
    const auto& a = j["accessors"][accessor];
    const auto& v = j["bufferViews"][a["bufferView"].get<int>()];
    const size_t n = a["count"].get<size_t>() * (a["type"] == "VEC3" ? 3 : 1);
    std::vector<float> out(n);
    std::memcpy(out.data(), buf.data() + v["byteOffset"].get<size_t>(), n * 4);
    return out;
  };
  const int S = rig.num_surface_vertices();
  const std::vector<float> pos = floats(prim["attributes"]["POSITION"]);
  ASSERT_EQ(pos.size(), size_t(S) * 3);
  EXPECT_EQ(std::memcmp(pos.data(), seq.frame_surface(0), pos.size() * 4), 0);
  const int t2 = prim["targets"][1]["POSITION"];
  EXPECT_TRUE(j["accessors"][t2].contains("min") && j["accessors"][t2].contains("max"));
  const std::vector<float> d2 = floats(t2);
  for (size_t i = 0; i < d2.size(); ++i) ASSERT_EQ(d2[i], seq.frame_surface(2)[i] - seq.frame_surface(0)[i]);
  const auto& sampler = j["animations"][0]["samplers"][0];
  EXPECT_EQ(sampler["interpolation"], "STEP");
  const std::vector<float> times = floats(sampler["input"]);
  ASSERT_EQ(times.size(), 4u);
  EXPECT_FLOAT_EQ(times[3], 3 / 30.0f);
  const std::vector<float> weights = floats(sampler["output"]);
  ASSERT_EQ(weights.size(), 4u * 3u);
  EXPECT_EQ(weights[2 * 3 + 1], 1.0f);  // frame 2 shows target 1 alone
  EXPECT_EQ(weights[2 * 3 + 0], 0.0f);
  const auto& idx_acc = j["accessors"][prim["indices"].get<int>()];
  EXPECT_EQ(idx_acc["count"].get<long>(), rig.surface_tris.rows() * 3);
  EXPECT_EQ(idx_acc["componentType"], 5125);

  // Chosen frames; errors.
  write_sequence_gltf(rig, seq, path, {1, 3});
  EXPECT_HAS(error_of([&] { write_sequence_gltf(rig, seq, path, {3, 1}); }), "increasing order");
  EXPECT_HAS(error_of([&] { write_sequence_gltf(rig, seq, path, {7}); }), "out of range");
  EXPECT_EQ(base64_encode("Man", 3), "TWFu");
  EXPECT_EQ(base64_encode("Ma", 2), "TWE=");
  EXPECT_EQ(base64_encode("M", 1), "TQ==");
}
