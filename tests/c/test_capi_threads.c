/* Several threads create contexts at once as the first thing a process does
   (the OpenCL driver's first platform query is not thread-safe; the engine
   must serialise it). Each thread then steps its context and reads the
   surface; all must succeed and agree. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facesr.h"

#define THREADS 4

static const facesr_rig* g_rig;
static const facesr_model* g_model;
static int g_count;

typedef struct {
  facesr_status status;
  float* positions;
  char message[512];
} result;

static void* worker(void* arg) {
  result* r = (result*)arg;
  facesr_context_def def = facesr_default_context_def();
  def.inference = FACESR_INFERENCE_CPU;
  facesr_context* c = NULL;
  r->status = facesr_context_create(g_rig, g_model, &def, &c);
  if (r->status == FACESR_OK) r->status = facesr_set_weight_by_name(c, "jawOpen", 0.5f);
  if (r->status == FACESR_OK) r->status = facesr_step(c);
  if (r->status == FACESR_OK) {
    r->positions = (float*)malloc(sizeof(float) * (size_t)g_count);
    r->status = facesr_get_positions(c, r->positions, g_count);
  }
  if (r->status != FACESR_OK) snprintf(r->message, sizeof r->message, "%s", facesr_last_error_message());
  facesr_context_destroy(c);
  return NULL;
}

int main(int argc, char** argv) {
  if (argc != 3) {
    fprintf(stderr, "usage: %s RIG MODEL\n", argv[0]);
    return 2;
  }
  facesr_rig* rig = NULL;
  facesr_model* model = NULL;
  if (facesr_rig_load(argv[1], &rig) != FACESR_OK || facesr_model_load(argv[2], &model) != FACESR_OK) {
    fprintf(stderr, "load failed: %s\n", facesr_last_error_message());
    return 1;
  }
  facesr_rig_info info;
  memset(&info, 0, sizeof info);
  info.struct_size = sizeof info;
  facesr_rig_get_info(rig, &info);
  g_rig = rig;
  g_model = model;
  g_count = 3 * info.num_surface_vertices;
  pthread_t t[THREADS];
  result r[THREADS];
  memset(r, 0, sizeof r);
  for (int i = 0; i < THREADS; ++i) pthread_create(&t[i], NULL, worker, &r[i]);
  for (int i = 0; i < THREADS; ++i) pthread_join(t[i], NULL);
  int failures = 0;
  for (int i = 0; i < THREADS; ++i) {
    if (r[i].status != FACESR_OK) {
      fprintf(stderr, "thread %d: %s: %s\n", i, facesr_status_name(r[i].status), r[i].message);
      ++failures;
    } else if (i > 0 && r[0].positions && memcmp(r[0].positions, r[i].positions, sizeof(float) * (size_t)g_count)) {
      fprintf(stderr, "thread %d: surface differs from thread 0\n", i);
      ++failures;
    }
  }
  for (int i = 0; i < THREADS; ++i) free(r[i].positions);
  facesr_model_free(model);
  facesr_rig_free(rig);
  if (failures == 0) printf("%d threads created contexts at once and agree\n", THREADS);
  return failures ? 1 : 0;
}
