#include "gltf_writer.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* glTF component and buffer-view target codes (the spec's GL enums). */
#define GL_FLOAT 5126
#define GL_UNSIGNED_INT 5125
#define GL_ARRAY_BUFFER 34962
#define GL_ELEMENT_ARRAY_BUFFER 34963

/* A data URI this large is beyond what viewers load comfortably. */
#define MAX_BUFFER_BYTES (1024.0 * 1024.0 * 1024.0)

/* ------------------------------------------------------------ base64 stream */

typedef struct b64_stream {
  FILE* f;
  unsigned char carry[3];
  int carried;
  char out[4096];
  size_t used;
} b64_stream;

static const char kB64[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

static void b64_flush(b64_stream* s) {
  if (s->used) fwrite(s->out, 1, s->used, s->f);
  s->used = 0;
}

static void b64_quad(b64_stream* s, const unsigned char* b, int n) {
  const unsigned v = (unsigned)b[0] << 16 | (unsigned)(n > 1 ? b[1] : 0) << 8 | (unsigned)(n > 2 ? b[2] : 0);
  if (s->used + 4 > sizeof s->out) b64_flush(s);
  s->out[s->used++] = kB64[(v >> 18) & 63];
  s->out[s->used++] = kB64[(v >> 12) & 63];
  s->out[s->used++] = n > 1 ? kB64[(v >> 6) & 63] : '=';
  s->out[s->used++] = n > 2 ? kB64[v & 63] : '=';
}

static void b64_put(b64_stream* s, const void* data, size_t size) {
  const unsigned char* p = (const unsigned char*)data;
  while (size > 0) {
    s->carry[s->carried++] = *p++;
    --size;
    if (s->carried == 3) {
      b64_quad(s, s->carry, 3);
      s->carried = 0;
    }
  }
}

static void b64_finish(b64_stream* s) {
  if (s->carried) b64_quad(s, s->carry, s->carried);
  s->carried = 0;
  b64_flush(s);
}

/* -------------------------------------------------------------- the layout */

typedef struct layout {
  int V, T, F;
  size_t idx_bytes, vec_bytes, times_bytes, weights_bytes;
  double total;
} layout;

static void make_layout(const gltf_animation* a, layout* l) {
  l->V = a->num_vertices;
  l->T = a->num_triangles;
  l->F = a->frames;
  l->idx_bytes = (size_t)l->T * 3 * 4;
  l->vec_bytes = (size_t)l->V * 3 * 4;
  l->times_bytes = (size_t)l->F * 4;
  l->weights_bytes = (size_t)l->F * (size_t)l->F * 4;
  l->total = (double)l->idx_bytes + 2.0 * l->vec_bytes * (1.0 + l->F) + l->times_bytes + (double)l->weights_bytes;
}

/* Element i of frame f's offset from the rest, computed the same way for
 * min/max and for the bytes written, so the two always agree. */
static float delta(const float* frames, const float* rest, int f, size_t V3, size_t i) {
  return frames[(size_t)f * V3 + i] - rest[i];
}

static void write_vec3_accessor(FILE* o, int view, int count, const float* base, const float* rest, int f,
                                int with_bounds, int first) {
  const size_t n = (size_t)count * 3;
  float lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  size_t i;
  if (with_bounds) {
    for (i = 0; i < n; ++i) {
      const float v = rest ? delta(base, rest, f, n, i) : base[i];
      const int c = (int)(i % 3);
      if (i < 3 || v < lo[c]) lo[c] = v;
      if (i < 3 || v > hi[c]) hi[c] = v;
    }
  }
  fprintf(o, "%s{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"VEC3\"", first ? "" : ",", view,
          GL_FLOAT, count);
  if (with_bounds)
    fprintf(o, ",\"min\":[%.9g,%.9g,%.9g],\"max\":[%.9g,%.9g,%.9g]", (double)lo[0], (double)lo[1], (double)lo[2],
            (double)hi[0], (double)hi[1], (double)hi[2]);
  fputc('}', o);
}

static void write_json_string(FILE* o, const char* s) {
  fputc('"', o);
  for (; *s; ++s) {
    const unsigned char c = (unsigned char)*s;
    if (c == '"' || c == '\\')
      fprintf(o, "\\%c", c);
    else if (c < 0x20)
      fprintf(o, "\\u%04x", c);
    else
      fputc(c, o);
  }
  fputc('"', o);
}

static void write_json(FILE* o, const gltf_animation* a, const layout* l) {
  const int F = l->F;
  const int n_views = 5 + 2 * F;
  size_t offset = 0;
  int v, f;
  const double s = a->metres_per_unit;

  fprintf(o,
          "{\"asset\":{\"version\":\"2.0\",\"generator\":\"facesr_play_c\"},\"scene\":0,"
          "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"name\":");
  write_json_string(o, a->name ? a->name : "face");
  fprintf(o, ",\"mesh\":0,\"scale\":[%.9g,%.9g,%.9g]}],", s, s, s);

  /* Accessors: 0 indices, 1 rest position, 2 rest normal, then per frame a
     position and a normal offset, then the animation's times and weights.
     Accessor i reads buffer view i. */
  fprintf(o,
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":1,\"NORMAL\":2},\"indices\":0,\"mode\":4,"
          "\"targets\":[");
  for (f = 0; f < F; ++f) fprintf(o, "%s{\"POSITION\":%d,\"NORMAL\":%d}", f ? "," : "", 3 + 2 * f, 4 + 2 * f);
  fprintf(o, "]}],\"weights\":[");
  for (f = 0; f < F; ++f) fprintf(o, "%s0", f ? "," : "");
  fprintf(o, "],\"extras\":{\"targetNames\":[");
  for (f = 0; f < F; ++f) fprintf(o, "%s\"frame %d\"", f ? "," : "", f);
  fprintf(o, "]}}],");

  fprintf(o, "\"accessors\":[{\"bufferView\":0,\"componentType\":%d,\"count\":%d,\"type\":\"SCALAR\"}", GL_UNSIGNED_INT,
          3 * l->T);
  write_vec3_accessor(o, 1, l->V, a->rest_positions, NULL, 0, 1, 0);
  write_vec3_accessor(o, 2, l->V, a->rest_normals, NULL, 0, 0, 0);
  for (f = 0; f < F; ++f) {
    write_vec3_accessor(o, 3 + 2 * f, l->V, a->positions, a->rest_positions, f, 1, 0);
    write_vec3_accessor(o, 4 + 2 * f, l->V, a->normals, a->rest_normals, f, 0, 0);
  }
  fprintf(o,
          ",{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"SCALAR\",\"min\":[0],"
          "\"max\":[%.9g]}",
          3 + 2 * F, GL_FLOAT, F, (double)(float)((F - 1) / a->fps));
  fprintf(o, ",{\"bufferView\":%d,\"componentType\":%d,\"count\":%d,\"type\":\"SCALAR\"}],", 4 + 2 * F, GL_FLOAT,
          F * F);

  fprintf(o,
          "\"animations\":[{\"name\":\"performance\",\"samplers\":[{\"input\":%d,\"output\":%d,"
          "\"interpolation\":\"LINEAR\"}],\"channels\":[{\"sampler\":0,\"target\":{\"node\":0,\"path\":"
          "\"weights\"}}]}],",
          3 + 2 * F, 4 + 2 * F);

  fprintf(o, "\"bufferViews\":[");
  for (v = 0; v < n_views; ++v) {
    size_t len;
    int target;
    if (v == 0) {
      len = l->idx_bytes;
      target = GL_ELEMENT_ARRAY_BUFFER;
    } else if (v < 3 + 2 * F) {
      len = l->vec_bytes;
      target = GL_ARRAY_BUFFER;
    } else {
      len = v == 3 + 2 * F ? l->times_bytes : l->weights_bytes;
      target = 0;
    }
    fprintf(o, "%s{\"buffer\":0,\"byteOffset\":%.0f,\"byteLength\":%.0f", v ? "," : "", (double)offset, (double)len);
    if (target) fprintf(o, ",\"target\":%d", target);
    fputc('}', o);
    offset += len;
  }
  fprintf(o, "],\"buffers\":[{\"byteLength\":%.0f,\"uri\":\"data:application/octet-stream;base64,", l->total);
}

static void write_binary(b64_stream* s, const gltf_animation* a, const layout* l) {
  const size_t V3 = (size_t)l->V * 3;
  float chunk[1024];
  size_t i;
  int f, g;
  for (i = 0; i < (size_t)l->T * 3; ++i) {
    const uint32_t idx = (uint32_t)a->triangles[i];
    b64_put(s, &idx, 4);
  }
  b64_put(s, a->rest_positions, l->vec_bytes);
  b64_put(s, a->rest_normals, l->vec_bytes);
  for (f = 0; f < l->F; ++f) {
    int which;
    for (which = 0; which < 2; ++which) {
      const float* frames = which ? a->normals : a->positions;
      const float* rest = which ? a->rest_normals : a->rest_positions;
      size_t done = 0;
      while (done < V3) {
        const size_t n = V3 - done < 1024 ? V3 - done : 1024;
        for (i = 0; i < n; ++i) chunk[i] = delta(frames, rest, f, V3, done + i);
        b64_put(s, chunk, n * sizeof(float));
        done += n;
      }
    }
  }
  for (f = 0; f < l->F; ++f) {
    const float t = (float)(f / a->fps);
    b64_put(s, &t, 4);
  }
  /* Keyframe f is all of target f: linear interpolation between keyframes
     blends frame f into frame f + 1. */
  for (f = 0; f < l->F; ++f)
    for (g = 0; g < l->F; ++g) {
      const float w = f == g ? 1.0f : 0.0f;
      b64_put(s, &w, 4);
    }
  b64_finish(s);
}

static int all_finite(const float* v, size_t n) {
  size_t i;
  for (i = 0; i < n; ++i)
    if (!isfinite(v[i])) return 0;
  return 1;
}

static int check_input(const gltf_animation* a, const layout* l, char* err, size_t err_size) {
  const uint32_t one = 1;
  const size_t V3 = (size_t)a->num_vertices * 3;
  int i;
  if (*(const unsigned char*)&one != 1) {
    snprintf(err, err_size, "glTF buffers are little-endian; this host is not");
  } else if (a->num_vertices <= 0 || a->num_triangles <= 0 || a->frames <= 0 || !(a->fps > 0)) {
    snprintf(err, err_size, "nothing to write (%d vertices, %d triangles, %d frames)", a->num_vertices,
             a->num_triangles, a->frames);
  } else if (l->total > MAX_BUFFER_BYTES) {
    snprintf(err, err_size, "%d frames make a %.0f MB buffer; write fewer frames (--frames)", a->frames,
             l->total / 1e6);
  } else if (!all_finite(a->rest_positions, V3) || !all_finite(a->rest_normals, V3) ||
             !all_finite(a->positions, V3 * (size_t)a->frames) || !all_finite(a->normals, V3 * (size_t)a->frames)) {
    snprintf(err, err_size, "the surface has non-finite values");
  } else {
    for (i = 0; i < 3 * a->num_triangles; ++i)
      if (a->triangles[i] < 0 || a->triangles[i] >= a->num_vertices) {
        snprintf(err, err_size, "triangle index %d is out of range", a->triangles[i]);
        return -1;
      }
    return 0;
  }
  return -1;
}

int gltf_write_animation(const char* path, const gltf_animation* a, char* err, size_t err_size) {
  layout l;
  char* tmp;
  FILE* o;
  b64_stream s;
  int failed;
  make_layout(a, &l);
  if (check_input(a, &l, err, err_size) != 0) return -1;
  if (!(tmp = (char*)malloc(strlen(path) + 9))) {
    snprintf(err, err_size, "out of memory");
    return -1;
  }
  sprintf(tmp, "%s.partial", path);
  if (!(o = fopen(tmp, "wb"))) {
    snprintf(err, err_size, "cannot create %s", tmp);
    free(tmp);
    return -1;
  }
  write_json(o, a, &l);
  memset(&s, 0, sizeof s);
  s.f = o;
  write_binary(&s, a, &l);
  fputs("\"}]}\n", o);
  failed = ferror(o) != 0;
  failed |= fclose(o) != 0;
#if defined(_WIN32)
  if (!failed) remove(path); /* rename does not replace an existing file there */
#endif
  if (failed || rename(tmp, path) != 0) {
    snprintf(err, err_size, failed ? "cannot write %s (disk full?)" : "cannot rename %s into place", tmp);
    remove(tmp);
    free(tmp);
    return -1;
  }
  free(tmp);
  return 0;
}
