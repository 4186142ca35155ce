/* The C ABI from plain C99: load, step, read back, and the documented error
 * codes, with the context still usable after every error.
 *   facesr_capi_c_test RIG MODEL */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "facesr.h"

static int failures = 0;

#define CHECK(cond)                                                            \
  do {                                                                         \
    if (!(cond)) {                                                             \
      fprintf(stderr, "%s:%d: CHECK failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                              \
    }                                                                          \
  } while (0)

/* The call must return `want`; a failure must leave a message. */
#define EXPECT_STATUS(want, call) expect_status((want), (call), #call, __LINE__)

static void expect_status(facesr_status want, facesr_status got, const char* call, int line) {
  if (got != want) {
    fprintf(stderr, "line %d: %s returned %s, expected %s (message: %s)\n", line, call, facesr_status_name(got),
            facesr_status_name(want), facesr_last_error_message());
    ++failures;
  } else if (want != FACESR_OK && facesr_last_error_message()[0] == '\0') {
    fprintf(stderr, "line %d: %s failed without a message\n", line, call);
    ++failures;
  }
}

static int all_finite(const float* v, int64_t n) {
  int64_t i;
  for (i = 0; i < n; ++i)
    if (!isfinite(v[i])) return 0;
  return 1;
}

static double max_abs_diff(const float* a, const float* b, int64_t n) {
  double worst = 0;
  int64_t i;
  for (i = 0; i < n; ++i)
    if (fabs((double)a[i] - b[i]) > worst) worst = fabs((double)a[i] - b[i]);
  return worst;
}

static void test_status_names(void) {
  CHECK(facesr_abi_version() == FACESR_ABI_VERSION);
  CHECK(strncmp(facesr_version_string(), "facesr ", 7) == 0);
  CHECK(strcmp(facesr_status_name(FACESR_OK), "FACESR_OK") == 0);
  CHECK(strcmp(facesr_status_name(FACESR_ERROR_BUFFER_SIZE), "FACESR_ERROR_BUFFER_SIZE") == 0);
  CHECK(strcmp(facesr_status_name(FACESR_ERROR_INTERNAL), "FACESR_ERROR_INTERNAL") == 0);
  CHECK(strcmp(facesr_status_name(-1), "unknown") == 0);
  CHECK(strcmp(facesr_status_name(1000), "unknown") == 0);
}

static void test_load_errors(const char* rig_path, const char* model_path) {
  facesr_rig* rig = (facesr_rig*)&rig; /* must be reset to NULL on failure */
  facesr_model* model = NULL;
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_load(NULL, &rig));
  CHECK(rig == NULL);
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_load(rig_path, NULL));
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load("/nonexistent/x.rig", &rig));
  CHECK(strstr(facesr_last_error_message(), "/nonexistent/x.rig") != NULL);
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_rig_load(model_path, &rig)); /* a model is not a rig */
  CHECK(rig == NULL);
  EXPECT_STATUS(FACESR_ERROR_FILE, facesr_model_load(rig_path, &model));
  CHECK(model == NULL);
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_model_load(NULL, &model));
  facesr_rig_free(NULL);
  facesr_model_free(NULL);
  facesr_context_destroy(NULL);
}

static void test_rig(const facesr_rig* rig, const facesr_model* model, facesr_rig_info* info) {
  facesr_model_info minfo;
  char name[64];
  int32_t len = -1, index = -1;
  info->struct_size = 0;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_get_info(rig, info));
  info->struct_size = sizeof *info;
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_get_info(NULL, info));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_get_info(rig, NULL));
  EXPECT_STATUS(FACESR_OK, facesr_rig_get_info(rig, info));
  CHECK(info->num_blendshapes > 0 && info->num_surface_vertices > 0 && info->num_surface_triangles > 0);
  CHECK(info->num_lr_nodes > 0 && info->num_muscles > 0);

  minfo.struct_size = sizeof minfo;
  EXPECT_STATUS(FACESR_OK, facesr_model_get_info(model, &minfo));
  CHECK(minfo.rig_checksum == info->checksum);
  CHECK(minfo.num_lr_nodes == info->num_lr_nodes && minfo.num_surface_vertices == info->num_surface_vertices);
  CHECK(minfo.num_parameters > 0);

  EXPECT_STATUS(FACESR_OK, facesr_rig_blendshape_name(rig, 0, name, sizeof name, &len));
  CHECK(len == (int32_t)strlen(name));
  EXPECT_STATUS(FACESR_OK, facesr_rig_blendshape_index(rig, name, &index));
  CHECK(index == 0);
  EXPECT_STATUS(FACESR_ERROR_NOT_FOUND, facesr_rig_blendshape_index(rig, "noSuchShape", &index));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_rig_blendshape_name(rig, info->num_blendshapes, name, 64, &len));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_blendshape_name(rig, 0, NULL, 64, &len));
}

static void test_geometry(const facesr_rig* rig, const facesr_rig_info* info) {
  const int64_t nt = 3 * (int64_t)info->num_surface_triangles, nv = 3 * (int64_t)info->num_surface_vertices;
  int32_t* tris = (int32_t*)malloc((size_t)nt * sizeof *tris);
  float* rest = (float*)malloc((size_t)nv * sizeof *rest);
  int64_t i;
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_rig_get_triangles(rig, tris, nt - 1));
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_rig_get_triangles(rig, tris, nt + 1));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_rig_get_triangles(rig, NULL, nt));
  EXPECT_STATUS(FACESR_OK, facesr_rig_get_triangles(rig, tris, nt));
  for (i = 0; i < nt; ++i) CHECK(tris[i] >= 0 && tris[i] < info->num_surface_vertices);
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_rig_get_rest_positions(rig, rest, nv / 3));
  EXPECT_STATUS(FACESR_OK, facesr_rig_get_rest_positions(rig, rest, nv));
  CHECK(all_finite(rest, nv));
  free(tris);
  free(rest);
}

static facesr_context* create(const facesr_rig* rig, const facesr_model* model) {
  facesr_context_def def = facesr_default_context_def();
  facesr_context* ctx = NULL;
  def.inference = FACESR_INFERENCE_CPU;
  EXPECT_STATUS(FACESR_OK, facesr_context_create(rig, model, &def, &ctx));
  return ctx;
}

static void test_create_errors(const facesr_rig* rig, const facesr_model* model) {
  facesr_context_def def = facesr_default_context_def();
  facesr_context* ctx = NULL;
  def.inference = FACESR_INFERENCE_CPU;
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_context_create(NULL, model, &def, &ctx));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_context_create(rig, NULL, &def, &ctx));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_context_create(rig, model, &def, NULL));
  def.struct_size = 8;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig, model, &def, &ctx));
  def.struct_size = sizeof def;
  def.solver = 7;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_context_create(rig, model, &def, &ctx));
  def.solver = FACESR_SOLVER_REALTIME;
  def.device_name = "no-such-opencl-device";
  EXPECT_STATUS(FACESR_ERROR_DEVICE, facesr_context_create(rig, model, &def, &ctx));
  CHECK(ctx == NULL);
}

static void test_context(facesr_context* ctx, const facesr_rig_info* info) {
  const int64_t n = 3 * (int64_t)info->num_surface_vertices;
  float* rest = (float*)malloc((size_t)n * sizeof *rest);
  float* pos = (float*)malloc((size_t)n * sizeof *pos);
  float* w = (float*)calloc((size_t)info->num_blendshapes, sizeof *w);
  facesr_frame_stats st;
  int64_t frame = -7;
  int32_t pending = -1;

  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, rest, n)); /* the rest pose before any step */
  st.struct_size = sizeof st;
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.frame == -1);

  /* NULL handles and arguments. */
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_step(NULL));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_step_async(NULL));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_wait(NULL, &frame));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_get_positions(NULL, pos, n));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_get_positions(ctx, NULL, n));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_set_weight(NULL, 0, 0.5f));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_set_weight_by_name(ctx, NULL, 0.5f));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_context_reset(NULL));
  EXPECT_STATUS(FACESR_ERROR_NULL_ARGUMENT, facesr_pending_frames(ctx, NULL));

  /* Wrong buffer sizes: the message gives the required count. */
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_positions(ctx, pos, n - 3));
  {
    char required[32];
    sprintf(required, "%lld", (long long)n);
    CHECK(strstr(facesr_last_error_message(), required) != NULL);
  }
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_normals(ctx, pos, 0));
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_get_embedded_positions(ctx, pos, n + 1));
  EXPECT_STATUS(FACESR_ERROR_BUFFER_SIZE, facesr_set_weights(ctx, w, info->num_blendshapes - 1));

  /* Bad values, unknown names, misuse of the pipeline. */
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(ctx, 0, (float)NAN));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(ctx, 0, 1.5f));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(ctx, 0, 1.11f));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(ctx, 0, -0.11f));
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weight(ctx, -1, 0.5f));
  w[0] = (float)NAN;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weights(ctx, w, info->num_blendshapes));
  w[0] = 0;
  EXPECT_STATUS(FACESR_ERROR_NOT_FOUND, facesr_set_weight_by_name(ctx, "jawopen_typo", 0.5f));
  CHECK(strstr(facesr_last_error_message(), "jawopen_typo") != NULL);
  EXPECT_STATUS(FACESR_ERROR_STATE, facesr_wait(ctx, &frame));
  st.struct_size = 2;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_get_frame_stats(ctx, &st));

  /* Still usable: the failed calls changed nothing. */
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(max_abs_diff(pos, rest, n) == 0);
  EXPECT_STATUS(FACESR_OK, facesr_set_weight_by_name(ctx, "jawOpen", 0.8f));
  EXPECT_STATUS(FACESR_OK, facesr_step(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(all_finite(pos, n));
  CHECK(max_abs_diff(pos, rest, n) > 0.01); /* the mouth opened (cm) */
  st.struct_size = sizeof st;
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.frame == 0 && st.newton_iterations > 0 && st.total_ms > 0);

  /* At most two frames in flight; no sync step while they are. */
  EXPECT_STATUS(FACESR_OK, facesr_step_async(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_step_async(ctx));
  EXPECT_STATUS(FACESR_ERROR_STATE, facesr_step_async(ctx));
  EXPECT_STATUS(FACESR_ERROR_STATE, facesr_step(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_pending_frames(ctx, &pending));
  CHECK(pending == 2);
  EXPECT_STATUS(FACESR_OK, facesr_wait(ctx, &frame));
  CHECK(frame == 1);
  EXPECT_STATUS(FACESR_OK, facesr_wait(ctx, NULL));
  EXPECT_STATUS(FACESR_ERROR_STATE, facesr_wait(ctx, &frame));
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.frame == 2);
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(all_finite(pos, n));

  EXPECT_STATUS(FACESR_OK, facesr_context_reset(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(max_abs_diff(pos, rest, n) == 0);
  free(rest);
  free(pos);
  free(w);
}

/* Capture overshoots within the documented tolerance are clamped, not refused. */
static void test_weight_tolerance(facesr_context* ctx, const facesr_rig_info* info) {
  float* w = (float*)calloc((size_t)info->num_blendshapes, sizeof *w);
  w[0] = 1.04f;
  w[1] = -0.05f;
  EXPECT_STATUS(FACESR_OK, facesr_set_weights(ctx, w, info->num_blendshapes));
  EXPECT_STATUS(FACESR_OK, facesr_set_weight(ctx, 0, 1.1f));
  EXPECT_STATUS(FACESR_OK, facesr_set_weight(ctx, 0, -0.1f));
  w[1] = 1.2f;
  EXPECT_STATUS(FACESR_ERROR_INVALID_ARGUMENT, facesr_set_weights(ctx, w, info->num_blendshapes));
  CHECK(strstr(facesr_last_error_message(), "1.1") != NULL); /* names the tolerance */
  EXPECT_STATUS(FACESR_OK, facesr_context_reset(ctx));
  free(w);
}

/* A frame the simulation cannot solve (the jaw thrown 3 m away) says so in
 * its status and returns the last good surface, and the next sane frame
 * plays again. */
static void test_divergence(facesr_context* ctx, const facesr_rig_info* info) {
  const int64_t n = 3 * (int64_t)info->num_surface_vertices;
  float* good = (float*)malloc((size_t)n * sizeof *good);
  float* pos = (float*)malloc((size_t)n * sizeof *pos);
  const float R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, far[3] = {0, -300, 0};
  facesr_frame_stats st;
  memset(&st, 0, sizeof st);
  st.struct_size = sizeof st;
  EXPECT_STATUS(FACESR_OK, facesr_set_weight_by_name(ctx, "jawOpen", 0.3f));
  EXPECT_STATUS(FACESR_OK, facesr_step(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.simulation_status == FACESR_FRAME_CONVERGED || st.simulation_status == FACESR_FRAME_UNCONVERGED);
  CHECK(st.recoveries == 0);
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, good, n));

  EXPECT_STATUS(FACESR_OK, facesr_set_jaw_transform(ctx, R, far));
  EXPECT_STATUS(FACESR_OK, facesr_step(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.simulation_status == FACESR_FRAME_DIVERGED);
  CHECK(st.recoveries > 0);
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(all_finite(pos, n));
  CHECK(max_abs_diff(pos, good, n) == 0); /* the last good surface, not the broken one */

  EXPECT_STATUS(FACESR_OK, facesr_clear_jaw_transform(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_step(ctx));
  EXPECT_STATUS(FACESR_OK, facesr_get_frame_stats(ctx, &st));
  CHECK(st.simulation_status != FACESR_FRAME_DIVERGED);
  EXPECT_STATUS(FACESR_OK, facesr_get_positions(ctx, pos, n));
  CHECK(all_finite(pos, n));
  EXPECT_STATUS(FACESR_OK, facesr_context_reset(ctx));
  free(good);
  free(pos);
}

int main(int argc, char** argv) {
  facesr_rig* rig = NULL;
  facesr_model* model = NULL;
  facesr_context* ctx;
  facesr_rig_info info;
  if (argc != 3) {
    fprintf(stderr, "usage: %s RIG MODEL\n", argv[0]);
    return 2;
  }
  test_status_names();
  test_load_errors(argv[1], argv[2]);
  EXPECT_STATUS(FACESR_OK, facesr_rig_load(argv[1], &rig));
  EXPECT_STATUS(FACESR_OK, facesr_model_load(argv[2], &model));
  if (!rig || !model) {
    fprintf(stderr, "cannot load the test rig and model\n");
    return 1;
  }
  test_rig(rig, model, &info);
  test_geometry(rig, &info);
  test_create_errors(rig, model);
  if ((ctx = create(rig, model)) != NULL) {
    test_context(ctx, &info);
    test_weight_tolerance(ctx, &info);
    test_divergence(ctx, &info);
    facesr_context_destroy(ctx);
  }
  facesr_model_free(model);
  facesr_rig_free(rig);
  if (failures) {
    fprintf(stderr, "%d check(s) failed\n", failures);
    return 1;
  }
  printf("C ABI test from C99: all checks passed\n");
  return 0;
}
