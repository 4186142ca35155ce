/* compare_frames: the played surfaces of several samples agree.
 *   compare_frames TOLERANCE_CM FLOATS_PER_FRAME a.bin b.bin [c.bin ...]
 *   compare_frames --self-test
 * Each file is raw little-endian float32, frames x FLOATS_PER_FRAME (the
 * samples' --out .bin / --dump-positions). All must hold the same number of
 * whole frames, be finite, move (the last frame is not the first), and lie
 * within TOLERANCE_CM of the first file everywhere. Exit 0 if so, else 1.
 * --self-test runs the comparison on made-up surfaces with known defects
 * and fails unless it catches every one. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct floats {
  const char* name;
  float* v;
  size_t n;
} floats;

static int load(const char* path, floats* out) {
  FILE* f = fopen(path, "rb");
  unsigned char b[4];
  size_t cap = 0;
  out->name = path;
  out->v = NULL;
  out->n = 0;
  if (!f) {
    fprintf(stderr, "compare_frames: cannot open %s\n", path);
    return -1;
  }
  for (;;) {
    const size_t got = fread(b, 1, 4, f);
    uint32_t u;
    if (got == 0) break;
    if (got != 4) {
      fprintf(stderr, "compare_frames: %s is not a whole number of float32 values\n", path);
      fclose(f);
      return -1;
    }
    if (out->n == cap) {
      float* grown;
      cap = cap ? 2 * cap : 4096;
      if (!(grown = (float*)realloc(out->v, cap * sizeof *grown))) {
        fclose(f);
        return -1;
      }
      out->v = grown;
    }
    u = (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
    memcpy(&out->v[out->n++], &u, sizeof u);
  }
  fclose(f);
  return 0;
}

/* 0 when every file agrees with f[0] as the header describes; 1 otherwise
 * (reasons on stderr). */
static int compare(const floats* f, int count, size_t per_frame, double tol) {
  const floats* a = &f[0];
  double moved = 0;
  size_t k, frames;
  int i, bad = 0;
  if (a->n == 0 || a->n % per_frame != 0) {
    fprintf(stderr, "compare_frames: %s holds %lu floats, not a positive multiple of %lu\n", a->name,
            (unsigned long)a->n, (unsigned long)per_frame);
    return 1;
  }
  frames = a->n / per_frame;
  for (k = 0; k < a->n; ++k)
    if (!isfinite(a->v[k])) {
      fprintf(stderr, "compare_frames: %s has a non-finite value at %lu\n", a->name, (unsigned long)k);
      return 1;
    }
  for (k = 0; k < per_frame; ++k) {
    const double d = fabs((double)a->v[(frames - 1) * per_frame + k] - a->v[k]);
    if (d > moved) moved = d;
  }
  if (frames > 1 && moved == 0) {
    fprintf(stderr, "compare_frames: %s does not move: its last frame equals its first\n", a->name);
    bad = 1;
  }
  for (i = 1; i < count; ++i) {
    const floats* b = &f[i];
    double worst = 0;
    size_t at = 0;
    if (b->n != a->n) {
      fprintf(stderr, "compare_frames: %s holds %lu floats, %s %lu\n", b->name, (unsigned long)b->n, a->name,
              (unsigned long)a->n);
      bad = 1;
      continue;
    }
    for (k = 0; k < a->n; ++k) {
      const double d = fabs((double)b->v[k] - a->v[k]);
      if (!(d <= worst)) { /* NaN too */
        worst = isnan(d) ? INFINITY : d;
        at = k;
      }
    }
    printf("%s vs %s: %lu frames, max |difference| %.3g cm (frame %lu, vertex %lu)\n", b->name, a->name,
           (unsigned long)frames, worst, (unsigned long)(at / per_frame), (unsigned long)(at % per_frame / 3));
    if (!(worst <= tol)) {
      fprintf(stderr, "compare_frames: %s differs from %s by %.3g cm > %.3g cm\n", b->name, a->name, worst, tol);
      bad = 1;
    }
  }
  printf("the surface moves up to %.3g cm between the first and the last frame\n", moved);
  return bad;
}

/* Known-good and known-bad pairs of made-up surfaces (3 frames of 2 vertices). */
static int self_test(void) {
  enum { N = 18 };
  float good[N], same[N], close_enough[N], off[N], nan_in[N], still[N];
  floats f[2];
  int k, failures = 0;
  struct {
    const char* what;
    float* other;
    size_t n;
    int want;
  } cases[6];
  for (k = 0; k < N; ++k) {
    good[k] = 10.0f + 0.25f * (float)k;
    still[k] = 1.0f;
  }
  memcpy(same, good, sizeof good);
  memcpy(close_enough, good, sizeof good);
  memcpy(off, good, sizeof good);
  memcpy(nan_in, good, sizeof good);
  close_enough[7] += 5e-6f;
  off[7] += 3e-5f;
  nan_in[11] = (float)NAN;
  cases[0].what = "identical";          cases[0].other = same;         cases[0].n = N;     cases[0].want = 0;
  cases[1].what = "within tolerance";   cases[1].other = close_enough; cases[1].n = N;     cases[1].want = 0;
  cases[2].what = "3e-5 cm off";        cases[2].other = off;          cases[2].n = N;     cases[2].want = 1;
  cases[3].what = "NaN";                cases[3].other = nan_in;       cases[3].n = N;     cases[3].want = 1;
  cases[4].what = "a frame short";      cases[4].other = same;         cases[4].n = N - 6; cases[4].want = 1;
  cases[5].what = "half a frame short"; cases[5].other = same;         cases[5].n = N - 3; cases[5].want = 1;
  for (k = 0; k < 6; ++k) {
    int got;
    f[0].name = "reference";
    f[0].v = good;
    f[0].n = N;
    f[1].name = cases[k].what;
    f[1].v = cases[k].other;
    f[1].n = cases[k].n;
    got = compare(f, 2, 6, 1e-5);
    if (got != cases[k].want) {
      fprintf(stderr, "self-test '%s': compare returned %d, expected %d\n", cases[k].what, got, cases[k].want);
      ++failures;
    }
  }
  f[0].name = "still";
  f[0].v = still;
  f[0].n = N;
  f[1] = f[0];
  if (compare(f, 2, 6, 1e-5) != 1) {
    fprintf(stderr, "self-test: a surface that does not move passed\n");
    ++failures;
  }
  printf(failures ? "compare_frames self-test FAILED\n" : "compare_frames self-test: every defect caught\n");
  return failures ? 1 : 0;
}

int main(int argc, char** argv) {
  floats files[16];
  double tol;
  long per_frame;
  int i, rc;
  if (argc == 2 && strcmp(argv[1], "--self-test") == 0) return self_test();
  if (argc < 5 || argc - 3 > 16) {
    fprintf(stderr, "usage: compare_frames TOLERANCE_CM FLOATS_PER_FRAME a.bin b.bin [c.bin ...] (at most 16)\n"
                    "       compare_frames --self-test\n");
    return 2;
  }
  tol = atof(argv[1]);
  per_frame = atol(argv[2]);
  if (!(tol >= 0) || per_frame <= 0) {
    fprintf(stderr, "compare_frames: bad tolerance or frame size\n");
    return 2;
  }
  for (i = 3; i < argc; ++i)
    if (load(argv[i], &files[i - 3]) != 0) return 1;
  rc = compare(files, argc - 3, (size_t)per_frame, tol);
  for (i = 3; i < argc; ++i) free(files[i - 3].v);
  return rc;
}
