/* A performance keyframe file (format "facesr-performance", version 1, see
 * docs/performances.md) sampled into per-frame weights, the same way the
 * engine samples it: frame f at t_first + f / fps up to the last keyframe,
 * linear interpolation between keyframes, a shape a keyframe does not list is
 * 0 at that keyframe. */
#ifndef FACESR_SAMPLE_PERFORMANCE_H
#define FACESR_SAMPLE_PERFORMANCE_H

#include <stddef.h>

typedef struct performance {
  double fps;
  int frames;
  int num_names;
  char** names;   /* every blendshape some keyframe lists, in order of first appearance */
  float* weights; /* frames × num_names, row-major */
  int has_jaw;    /* the file has explicit jaw transforms (the sample does not play them) */
} performance;

/* 0 on success; otherwise -1 with "path: problem" in err. */
int performance_load(const char* path, performance* out, char* err, size_t err_size);
void performance_free(performance* p);

#endif
