#pragma once
#include <vector>

#include "core/types.h"
#include "render/preview_raster.h"

// Software rasterizer for looking at simulated faces: z-buffered,
// Lambert-shaded triangles under an orthographic front view.
namespace facesr {

// Orthographic front view of a box onto a pixel rectangle of an image: the
// camera sits on +z looking toward -z (faces in facesr look along +z), world
// +x is image right, world +y is image up. One scale for both axes.
struct FrontView {
  Vec3 centre = Vec3::Zero();  // world point at the rectangle's centre (cm)
  double px_per_cm = 1;
  int x0 = 0, y0 = 0, width = 1, height = 1;

  // Image x, image y (pixels) and depth (cm, larger is farther from the camera).
  Vec3 project(const Vec3& p) const {
    const Vec3 d = p - centre;
    return Vec3(x0 + 0.5 * width + d.x() * px_per_cm, y0 + 0.5 * height - d.y() * px_per_cm, -d.z());
  }
};

// Frames the box [lo, hi] in the rectangle so that it fills `fill` of the
// tighter axis. Pass one box for several frames to keep them comparable.
FrontView frame_front_view(const Vec3& lo, const Vec3& hi, int x0, int y0, int width, int height, double fill = 0.9);

// Grows [lo, hi] to include n points stored as xyz floats.
void extend_box(const float* xyz, size_t n, Vec3& lo, Vec3& hi);

// Area-weighted vertex normals of a triangle mesh given as xyz floats.
std::vector<Vec3> vertex_normals_xyz(const float* xyz, int num_vertices, const Tris& tris);

// Draws the mesh into the view's rectangle (pixels outside it are left
// alone). Colour per vertex (interpolated), or `colour` when vertex_colour is
// empty; shaded by ambient + Lambert under a fixed light from the upper left
// front, two-sided so open boundaries and lips do not render black.
// Throws Error on a triangle index out of range or a colour count mismatch.
void rasterize_mesh(Image& img, const FrontView& view, const float* xyz, int num_vertices, const Tris& tris,
                    const std::vector<Rgb>& vertex_colour, Rgb colour);

}  // namespace facesr
