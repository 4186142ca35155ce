/* Writes an animated surface as one self-contained glTF 2.0 file: the rest
 * mesh, one morph target per frame (position and normal offsets from the
 * rest), and a weight animation that blends from each frame's target to the
 * next (LINEAR), so Blender (shape keys) and three.js (morph targets) play it
 * back at the performance's frame rate. The buffer is embedded as a base64
 * data URI. Meant for clips of seconds: the file grows with frames². */
#ifndef FACESR_SAMPLE_GLTF_WRITER_H
#define FACESR_SAMPLE_GLTF_WRITER_H

#include <stddef.h>
#include <stdint.h>

typedef struct gltf_animation {
  int num_vertices;
  int num_triangles;
  const int32_t* triangles;    /* 3 × num_triangles, counter-clockwise from outside */
  const float* rest_positions; /* 3 × num_vertices */
  const float* rest_normals;   /* 3 × num_vertices, unit */
  int frames;
  const float* positions; /* frames × 3 × num_vertices */
  const float* normals;   /* frames × 3 × num_vertices, unit */
  double fps;
  double metres_per_unit; /* node scale: glTF is in metres; 0.01 for centimetres */
  const char* name;
} gltf_animation;

/* Writes to a temporary file beside `path` and renames it into place, so a
 * failure never leaves a partial file at `path`. 0 on success; otherwise -1
 * with the problem in err. */
int gltf_write_animation(const char* path, const gltf_animation* a, char* err, size_t err_size);

#endif
