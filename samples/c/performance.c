#include "performance.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json.h"

/* The engine's bounds: at most 1000 fps, at most a day of frames at 30 fps. */
#define MAX_FPS 1000.0
#define MAX_FRAMES 3e6

typedef struct keyframe {
  double time;
  float* w; /* num_names values */
} keyframe;

static int name_slot(performance* p, const char* name) {
  int i;
  char** grown;
  for (i = 0; i < p->num_names; ++i)
    if (strcmp(p->names[i], name) == 0) return i;
  grown = (char**)realloc(p->names, (size_t)(p->num_names + 1) * sizeof *grown);
  if (!grown) return -1;
  p->names = grown;
  if (!(p->names[p->num_names] = (char*)malloc(strlen(name) + 1))) return -1;
  strcpy(p->names[p->num_names], name);
  return p->num_names++;
}

/* Collects every listed name first, so that each keyframe's row has them all. */
static int collect_names(performance* p, const json_value* keys, const char* path, char* err, size_t err_size) {
  size_t k, m;
  for (k = 0; k < keys->count; ++k) {
    const json_value* key = &keys->items[k];
    const json_value* w = json_get(key, "weights");
    if (key->type != JSON_OBJECT) {
      snprintf(err, err_size, "%s: keyframe %d is not an object", path, (int)k);
      return -1;
    }
    if (!w || w->type != JSON_OBJECT) {
      snprintf(err, err_size, "%s: keyframe %d: 'weights' is missing or not an object of name: weight", path, (int)k);
      return -1;
    }
    for (m = 0; m < w->count; ++m)
      if (name_slot(p, w->keys[m]) < 0) {
        snprintf(err, err_size, "%s: out of memory", path);
        return -1;
      }
  }
  return 0;
}

static int parse_keyframe(const performance* p, const json_value* key, int k, keyframe* out, const char* path,
                          char* err, size_t err_size) {
  const json_value* t = json_get(key, "time");
  const json_value* w = json_get(key, "weights");
  size_t m;
  int i;
  if (!t || t->type != JSON_NUMBER || !isfinite(t->number)) {
    snprintf(err, err_size, "%s: keyframe %d: 'time' is missing or not a finite number", path, k);
    return -1;
  }
  out->time = t->number;
  for (m = 0; m < w->count; ++m) {
    const double v = w->items[m].number;
    if (w->items[m].type != JSON_NUMBER || !(v >= 0 && v <= 1)) {
      snprintf(err, err_size, "%s: keyframe %d: weight '%s' is not a number in [0, 1]", path, k, w->keys[m]);
      return -1;
    }
    for (i = 0; i < p->num_names; ++i)
      if (strcmp(p->names[i], w->keys[m]) == 0) out->w[i] = (float)v;
  }
  return 0;
}

/* Weights at time t, with `k` the keyframe at or before it. Times within
 * rounding of a keyframe take it exactly, as the engine does. */
static void sample(const keyframe* keys, int nkeys, int k, double t, int n, float* out) {
  double alpha;
  int i;
  if (k + 1 >= nkeys) {
    memcpy(out, keys[k].w, (size_t)n * sizeof *out);
    return;
  }
  alpha = (t - keys[k].time) / (keys[k + 1].time - keys[k].time);
  if (alpha <= 1e-9) {
    memcpy(out, keys[k].w, (size_t)n * sizeof *out);
  } else if (alpha >= 1 - 1e-9) {
    memcpy(out, keys[k + 1].w, (size_t)n * sizeof *out);
  } else {
    for (i = 0; i < n; ++i) out[i] = (float)(keys[k].w[i] + alpha * ((double)keys[k + 1].w[i] - keys[k].w[i]));
  }
}

static int check_header(const json_value* root, const char* path, char* err, size_t err_size) {
  const json_value* format = json_get(root, "format");
  const json_value* version = json_get(root, "version");
  const json_value* fps = json_get(root, "fps");
  const json_value* keys = json_get(root, "keyframes");
  if (root->type != JSON_OBJECT) {
    snprintf(err, err_size, "%s: is not a JSON object", path);
  } else if (!format || format->type != JSON_STRING || strcmp(format->string, "facesr-performance") != 0) {
    snprintf(err, err_size, "%s: 'format' is not \"facesr-performance\"", path);
  } else if (!version || version->type != JSON_NUMBER || version->number != 1) {
    snprintf(err, err_size, "%s: 'version' is missing or not 1", path);
  } else if (!fps || fps->type != JSON_NUMBER || !(fps->number > 0 && fps->number <= MAX_FPS)) {
    snprintf(err, err_size, "%s: 'fps' is missing or not in (0, 1000]", path);
  } else if (!keys || keys->type != JSON_ARRAY || keys->count == 0) {
    snprintf(err, err_size, "%s: 'keyframes' is missing, not an array, or empty", path);
  } else {
    return 0;
  }
  return -1;
}

static int build(performance* p, const json_value* root, const char* path, char* err, size_t err_size) {
  const json_value* jk = json_get(root, "keyframes");
  const int nkeys = (int)jk->count;
  keyframe* keys = NULL;
  int k, f, ok = -1;
  double span;
  p->fps = json_get(root, "fps")->number;
  if (collect_names(p, jk, path, err, err_size) != 0) return -1;
  if (p->num_names == 0) {
    snprintf(err, err_size, "%s: no keyframe lists a weight", path);
    return -1;
  }
  if (!(keys = (keyframe*)calloc((size_t)nkeys, sizeof *keys))) goto oom;
  for (k = 0; k < nkeys; ++k) {
    const json_value* key = &jk->items[k];
    if (!(keys[k].w = (float*)calloc((size_t)p->num_names, sizeof(float)))) goto oom;
    if (parse_keyframe(p, key, k, &keys[k], path, err, err_size) != 0) goto done;
    if (k > 0 && !(keys[k].time > keys[k - 1].time)) {
      snprintf(err, err_size, "%s: keyframe %d: time %g is not after keyframe %d's time %g", path, k, keys[k].time,
               k - 1, keys[k - 1].time);
      goto done;
    }
    if (json_get(key, "jaw")) p->has_jaw = 1;
  }
  span = (keys[nkeys - 1].time - keys[0].time) * p->fps;
  if (!(span < MAX_FRAMES)) {
    snprintf(err, err_size, "%s: the keyframes span more than %g frames", path, MAX_FRAMES);
    goto done;
  }
  p->frames = (int)floor(span + 1e-6) + 1;
  if (!(p->weights = (float*)malloc((size_t)p->frames * (size_t)p->num_names * sizeof(float)))) goto oom;
  for (f = 0, k = 0; f < p->frames; ++f) {
    double t = keys[0].time + f / p->fps;
    if (t > keys[nkeys - 1].time) t = keys[nkeys - 1].time;
    while (k + 1 < nkeys && keys[k + 1].time <= t) ++k;
    sample(keys, nkeys, k, t, p->num_names, p->weights + (size_t)f * (size_t)p->num_names);
  }
  ok = 0;
  goto done;
oom:
  snprintf(err, err_size, "%s: out of memory", path);
done:
  if (keys)
    for (k = 0; k < nkeys; ++k) free(keys[k].w);
  free(keys);
  return ok;
}

int performance_load(const char* path, performance* out, char* err, size_t err_size) {
  char jerr[160];
  size_t length = 0;
  char* text = json_read_file(path, &length);
  json_value* root;
  int rc;
  memset(out, 0, sizeof *out);
  if (!text) {
    snprintf(err, err_size, "%s: cannot read the performance file", path);
    return -1;
  }
  root = json_parse(text, length, jerr, sizeof jerr);
  free(text);
  if (!root) {
    snprintf(err, err_size, "%s: not valid JSON: %s", path, jerr);
    return -1;
  }
  rc = check_header(root, path, err, err_size);
  if (rc == 0) rc = build(out, root, path, err, err_size);
  json_free(root);
  if (rc != 0) performance_free(out);
  return rc;
}

void performance_free(performance* p) {
  int i;
  for (i = 0; i < p->num_names; ++i) free(p->names[i]);
  free(p->names);
  free(p->weights);
  memset(p, 0, sizeof *p);
}
