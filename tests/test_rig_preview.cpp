#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/error.h"
#include "render/rig_preview.h"

#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wunused-function"
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

namespace facesr {
namespace {

// Axis-aligned box [lo, lo + n*h] split into cubes, each into 6 positively
// oriented tets sharing the cube's main diagonal.
TetMesh cube_grid(const Vec3& lo, double h, int nx, int ny, int nz) {
  TetMesh m;
  auto node = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  m.X.resize((nx + 1) * (ny + 1) * (nz + 1), 3);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) m.X.row(node(i, j, k)) = (lo + h * Vec3(i, j, k)).transpose();
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  std::vector<Vec4i> tets;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i)
        for (const auto& p : perms) {
          int c[3] = {i, j, k};
          Vec4i t;
          t[0] = node(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[p[s]];
            t[s + 1] = node(c[0], c[1], c[2]);
          }
          const Vec3 a = m.X.row(t[0]), b = m.X.row(t[1]), cc = m.X.row(t[2]), d = m.X.row(t[3]);
          if ((b - a).cross(cc - a).dot(d - a) < 0) std::swap(t[2], t[3]);
          tets.push_back(t);
        }
  m.T.resize(int(tets.size()), 4);
  for (size_t t = 0; t < tets.size(); ++t) m.T.row(t) = tets[t].transpose();
  return m;
}

// 4x4 cm patch at z = 0 facing +z over a 2 cm slab; the slab's x < 0 half is muscle 0.
Rig synthetic_rig() {
  Rig rig;
  rig.name = "synthetic_patch";
  const int n = 20;
  rig.surface.resize((n + 1) * (n + 1), 3);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      rig.surface.row(j * (n + 1) + i) << -2 + 4.0 * i / n, -2 + 4.0 * j / n, 0;
  rig.surface_tris.resize(2 * n * n, 3);
  for (int j = 0, f = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
      rig.surface_tris.row(f++) << a, b, d;
      rig.surface_tris.row(f++) << a, d, c;
    }
  rig.hr.mesh = cube_grid(Vec3(-2, -2, -2), 0.5, 8, 8, 4);
  for (int t = 0; t < rig.hr.mesh.T.rows(); ++t) {
    double cx = 0;
    for (int k = 0; k < 4; ++k) cx += 0.25 * rig.hr.mesh.X(rig.hr.mesh.T(t, k), 0);
    rig.hr.muscle.push_back(cx < 0 ? 0 : -1);
    rig.hr.muscle_fraction.push_back(cx < 0 ? 1.0f : 0.0f);
  }
  rig.muscles.resize(1);
  rig.muscles[0].name = "test_muscle";
  rig.lr.mesh = cube_grid(Vec3(-2.5, -2.5, -2.5), 2.5, 2, 2, 1);
  rig.lattice.origin = Vec3(-2.5, -2.5, -2.5);
  rig.lattice.cell = 2.5;
  rig.lattice.dims = {2, 2, 1};
  return rig;
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
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                             std::istreambuf_iterator<char>());
  const uint8_t signature[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1A, '\n'};
  EXPECT_GE(bytes.size(), 8u);
  EXPECT_TRUE(bytes.size() >= 8 && std::equal(signature, signature + 8, bytes.begin()));
  Decoded d;
  int channels = 0;
  uint8_t* px = stbi_load_from_memory(bytes.data(), int(bytes.size()), &d.w, &d.h, &channels, 3);
  EXPECT_NE(px, nullptr);
  if (px) {
    d.rgb.assign(px, px + size_t(d.w) * d.h * 3);
    stbi_image_free(px);
  }
  return d;
}

// Cosine between colours as RGB vectors: near 1 when one is a shaded version of the other.
double hue_similarity(Rgb a, Rgb b) {
  const Vec3 u(a.r, a.g, a.b), v(b.r, b.g, b.b);
  return u.dot(v) / std::max(1e-9, u.norm() * v.norm());
}

double distance(Rgb a, Rgb b) { return (Vec3(a.r, a.g, a.b) - Vec3(b.r, b.g, b.b)).norm(); }

std::string temp_png(const std::string& stem) {
  return (std::filesystem::temp_directory_path() /
          (stem + "_" + std::to_string(::getpid()) + ".png"))
      .string();
}

TEST(RigPreview, RendersMuscleColouredFrontAndSideViews) {
  const Rig rig = synthetic_rig();
  PreviewOptions opt;
  opt.width = 480;
  opt.height = 400;
  const std::string path = temp_png("facesr_rig_preview");
  render_rig_preview(rig, path, opt);
  ASSERT_TRUE(std::filesystem::exists(path));
  const Decoded img = decode_png(path);
  ASSERT_EQ(img.w, 480);
  ASSERT_EQ(img.h, 400);

  // The front panel is the left half; the patch is centred in it and fills
  // about 90% of its width, so x = 1/4 +- 1/8 of the image lands on each half.
  const int y = img.h / 2;
  const Rgb left = img.at(img.w / 4 - img.w / 8, y);
  const Rgb right = img.at(img.w / 4 + img.w / 8, y);
  const Rgb muscle = preview_muscle_colour({"test_muscle"}, 0);
  EXPECT_GT(hue_similarity(left, muscle), 0.995);
  EXPECT_GT(hue_similarity(right, preview_skin_colour()), 0.995);
  EXPECT_GT(distance(left, right), 60);

  // Background: the bottom strip of the front panel lies below the patch.
  const Rgb background = img.at(img.w / 4, img.h - 3);
  EXPECT_GT(distance(background, left), 40);
  EXPECT_GT(distance(background, right), 40);
  // The side view (right half) shows the same patch, foreshortened.
  EXPECT_GT(distance(img.at(3 * img.w / 4, y), background), 40);

  if (const char* keep = std::getenv("FACESR_PREVIEW_KEEP"))
    std::filesystem::copy_file(path, keep, std::filesystem::copy_options::overwrite_existing);
  std::filesystem::remove(path);
}

TEST(RigPreview, MirrorPairsShareHue) {
  const std::vector<std::string> names = {"zygomatic_L", "zygomatic_R", "frontalis"};
  const Rgb l = preview_muscle_colour(names, 0), r = preview_muscle_colour(names, 1);
  EXPECT_GT(hue_similarity(l, r), 0.999);
  EXPECT_GT(distance(l, r), 10);
  EXPECT_GT(distance(l, preview_muscle_colour(names, 2)), 60);
}

TEST(RigPreview, RejectsInvalidInput) {
  const Rig rig = synthetic_rig();
  const std::string path = temp_png("facesr_rig_preview_invalid");
  for (auto [w, h] :
       {std::pair{63, 400}, std::pair{400, 63}, std::pair{8193, 400}, std::pair{400, 9000}}) {
    PreviewOptions opt;
    opt.width = w;
    opt.height = h;
    EXPECT_THROW(render_rig_preview(rig, path, opt), Error) << w << "x" << h;
  }
  Rig empty = rig;
  empty.surface.resize(0, 3);
  empty.surface_tris.resize(0, 3);
  EXPECT_THROW(render_rig_preview(empty, path, PreviewOptions{}), Error);
  EXPECT_FALSE(std::filesystem::exists(path));
}

}  // namespace
}  // namespace facesr
