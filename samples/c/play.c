/* facesr_play_c: plays a performance through the C ABI the way a game loop
 * would (per frame: set weights by name, step, read the surface back) and
 * writes the animated high-resolution surface as a glTF 2.0 file.
 *
 *   facesr_play_c --rig R.rig --model M.fsm --performance P.json --out anim.gltf
 *                 [--frames N] [--async] [--split-device] [--inference auto|opencl|cpu] [--device NAME]
 *                 [--dump-positions frames.bin]
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "facesr.h"
#include "gltf_writer.h"
#include "performance.h"
#include "positions_dump.h"

typedef struct options {
  const char *rig, *model, *performance, *out, *device, *inference;
  const char* dump; /* --dump-positions: raw float32 of every frame, or NULL */
  int max_frames; /* -1: the whole performance */
  int async;
  int split_device; /* --split-device: half the device per stage (see facesr_context_def) */
} options;

static void usage(FILE* f) {
  fprintf(f,
          "usage: facesr_play_c --rig R.rig --model M.fsm --performance P.json --out anim.gltf\n"
          "                     [--frames N] [--async] [--split-device] [--inference auto|opencl|cpu]\n"
          "                     [--device NAME]\n"
          "                     [--dump-positions frames.bin]\n"
          "  --frames N     play at most the first N frames\n"
          "  --async        pipelined stepping (step_async + wait, one frame of latency)\n"
          "  --split-device half the device for the simulation, half for the inference\n"
          "  --inference    auto (default): OpenCL, else the CPU reference; or force one\n"
          "  --device NAME  OpenCL device (substring of device or platform name; default: first CPU)\n"
          "  --dump-positions FILE  also write every frame's positions as raw little-endian float32\n"
          "                 (frames x vertices x 3, cm), as the C# and Rust samples' --out .bin\n");
}

static int parse_args(int argc, char** argv, options* o) {
  int i;
  memset(o, 0, sizeof *o);
  o->max_frames = -1;
  o->inference = "auto";
  for (i = 1; i < argc; ++i) {
    const char* a = argv[i];
    const char** value = NULL;
    if (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0) {
      usage(stdout);
      exit(0);
    } else if (strcmp(a, "--async") == 0) {
      o->async = 1;
      continue;
    } else if (strcmp(a, "--split-device") == 0) {
      o->split_device = 1;
      continue;
    } else if (strcmp(a, "--rig") == 0) {
      value = &o->rig;
    } else if (strcmp(a, "--model") == 0) {
      value = &o->model;
    } else if (strcmp(a, "--performance") == 0) {
      value = &o->performance;
    } else if (strcmp(a, "--out") == 0 || strcmp(a, "-o") == 0) {
      value = &o->out;
    } else if (strcmp(a, "--device") == 0) {
      value = &o->device;
    } else if (strcmp(a, "--inference") == 0) {
      value = &o->inference;
    } else if (strcmp(a, "--dump-positions") == 0) {
      value = &o->dump;
    } else if (strcmp(a, "--frames") == 0) {
      char* end;
      long n;
      if (i + 1 >= argc) break;
      n = strtol(argv[++i], &end, 10);
      if (*end || n < 1 || n > 1000000) {
        fprintf(stderr, "facesr_play_c: --frames wants a positive number, got '%s'\n", argv[i]);
        return -1;
      }
      o->max_frames = (int)n;
      continue;
    } else {
      fprintf(stderr, "facesr_play_c: unknown option '%s'\n", a);
      usage(stderr);
      return -1;
    }
    if (i + 1 >= argc) break;
    *value = argv[++i];
  }
  if (i < argc) {
    fprintf(stderr, "facesr_play_c: %s needs a value\n", argv[i]);
    return -1;
  }
  if (!o->rig || !o->model || !o->performance || !o->out) {
    fprintf(stderr, "facesr_play_c: --rig, --model, --performance and --out are required\n");
    usage(stderr);
    return -1;
  }
  if (strcmp(o->inference, "auto") != 0 && strcmp(o->inference, "opencl") != 0 && strcmp(o->inference, "cpu") != 0) {
    fprintf(stderr, "facesr_play_c: --inference is auto, opencl or cpu, not '%s'\n", o->inference);
    return -1;
  }
  return 0;
}

/* Prints a failed call's status and message; returns nonzero on failure. */
static int failed(facesr_status s, const char* what) {
  if (s == FACESR_OK) return 0;
  fprintf(stderr, "facesr_play_c: %s: %s: %s\n", what, facesr_status_name(s), facesr_last_error_message());
  return 1;
}

static double now_seconds(void) {
  struct timespec ts;
  timespec_get(&ts, TIME_UTC);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static facesr_status create_context(const facesr_rig* rig, const facesr_model* model, const options* o,
                                    facesr_context** ctx) {
  facesr_context_def def = facesr_default_context_def();
  facesr_status s;
  def.device_name = o->device;
  def.inference = strcmp(o->inference, "cpu") == 0 ? FACESR_INFERENCE_CPU : FACESR_INFERENCE_OPENCL;
  def.split_device = o->split_device;
  s = facesr_context_create(rig, model, &def, ctx);
  if (s == FACESR_ERROR_DEVICE && strcmp(o->inference, "auto") == 0) {
    fprintf(stderr, "facesr_play_c: OpenCL inference unavailable (%s); using the CPU reference\n",
            facesr_last_error_message());
    def.inference = FACESR_INFERENCE_CPU;
    s = facesr_context_create(rig, model, &def, ctx);
  }
  return s;
}

/* Sets frame f's weights by name, as a game forwarding named controls would. */
static facesr_status set_frame_weights(facesr_context* ctx, const performance* perf, int f) {
  int i;
  for (i = 0; i < perf->num_names; ++i) {
    const facesr_status s =
        facesr_set_weight_by_name(ctx, perf->names[i], perf->weights[(size_t)f * (size_t)perf->num_names + (size_t)i]);
    if (s != FACESR_OK) return s;
  }
  return FACESR_OK;
}

static facesr_status read_frame(facesr_context* ctx, int64_t frame, int frames, int64_t n, float* positions,
                                float* normals, double* sim_ms, double* sr_ms) {
  facesr_frame_stats st;
  facesr_status s;
  st.struct_size = sizeof st;
  if (frame < 0 || frame >= frames) {
    fprintf(stderr, "facesr_play_c: frame %lld is not one that was submitted\n", (long long)frame);
    return FACESR_ERROR_INTERNAL;
  }
  if ((s = facesr_get_positions(ctx, positions + frame * n, n)) != FACESR_OK) return s;
  if ((s = facesr_get_normals(ctx, normals + frame * n, n)) != FACESR_OK) return s;
  if ((s = facesr_get_frame_stats(ctx, &st)) != FACESR_OK) return s;
  *sim_ms += st.simulation_ms;
  *sr_ms += st.inference_ms;
  return FACESR_OK;
}

/* The game loop. Async keeps one frame in flight: tick f submits frame f and
 * shows frame f - 1, so simulation and super-resolution overlap. */
static int play(facesr_context* ctx, const performance* perf, int frames, int async, int64_t n, float* positions,
                float* normals) {
  double sim_ms = 0, sr_ms = 0, t0, seconds;
  int f;
  int32_t pending = 0;
  int64_t done;
  t0 = now_seconds();
  for (f = 0; f < frames; ++f) {
    if (failed(set_frame_weights(ctx, perf, f), "set weights")) return -1;
    if (!async) {
      if (failed(facesr_step(ctx), "step") ||
          failed(read_frame(ctx, f, frames, n, positions, normals, &sim_ms, &sr_ms), "read"))
        return -1;
      continue;
    }
    if (failed(facesr_step_async(ctx), "step_async") || failed(facesr_pending_frames(ctx, &pending), "pending"))
      return -1;
    if (pending > 1 && (failed(facesr_wait(ctx, &done), "wait") ||
                        failed(read_frame(ctx, done, frames, n, positions, normals, &sim_ms, &sr_ms), "read")))
      return -1;
  }
  while (async) {
    if (failed(facesr_pending_frames(ctx, &pending), "pending")) return -1;
    if (pending == 0) break;
    if (failed(facesr_wait(ctx, &done), "wait") ||
        failed(read_frame(ctx, done, frames, n, positions, normals, &sim_ms, &sr_ms), "read"))
      return -1;
  }
  seconds = now_seconds() - t0;
  printf("played %d frames in %.2f s: %.1f FPS (%s; mean %.2f ms simulation, %.2f ms super-resolution per frame)\n",
         frames, seconds, seconds > 0 ? frames / seconds : 0.0, async ? "async" : "sync", sim_ms / frames,
         sr_ms / frames);
  return 0;
}

/* Every name the performance uses must be one of the rig's. */
static int check_names(const facesr_rig* rig, const performance* perf, const char* path) {
  int i;
  int32_t index;
  for (i = 0; i < perf->num_names; ++i)
    if (facesr_rig_blendshape_index(rig, perf->names[i], &index) != FACESR_OK) {
      fprintf(stderr, "facesr_play_c: %s: %s\n", path, facesr_last_error_message());
      return -1;
    }
  return 0;
}

int main(int argc, char** argv) {
  options o;
  facesr_rig* rig = NULL;
  facesr_model* model = NULL;
  facesr_context* ctx = NULL;
  facesr_rig_info info;
  performance perf;
  gltf_animation anim;
  char err[512];
  int frames, rc = 1;
  int64_t n;
  int32_t* tris = NULL;
  float *rest = NULL, *rest_n = NULL, *positions = NULL, *normals = NULL;

  memset(&perf, 0, sizeof perf);
  if (parse_args(argc, argv, &o) != 0) return 2;
  printf("%s (C ABI %u)\n", facesr_version_string(), (unsigned)facesr_abi_version());
  if (facesr_abi_version() != FACESR_ABI_VERSION) {
    fprintf(stderr, "facesr_play_c: built for ABI %d, the library has %u\n", FACESR_ABI_VERSION,
            (unsigned)facesr_abi_version());
    return 1;
  }
  if (failed(facesr_rig_load(o.rig, &rig), "load rig") || failed(facesr_model_load(o.model, &model), "load model"))
    goto done;
  info.struct_size = sizeof info;
  if (failed(facesr_rig_get_info(rig, &info), "rig info")) goto done;
  if (performance_load(o.performance, &perf, err, sizeof err) != 0) {
    fprintf(stderr, "facesr_play_c: %s\n", err);
    goto done;
  }
  if (check_names(rig, &perf, o.performance) != 0) goto done;
  if (perf.has_jaw)
    fprintf(stderr,
            "facesr_play_c: %s has explicit jaw transforms; they are not played (the jaw follows the "
            "jaw blendshapes)\n",
            o.performance);
  frames = o.max_frames > 0 && o.max_frames < perf.frames ? o.max_frames : perf.frames;
  if (failed(create_context(rig, model, &o, &ctx), "create context")) goto done;

  n = 3 * (int64_t)info.num_surface_vertices;
  tris = (int32_t*)malloc(3 * (size_t)info.num_surface_triangles * sizeof *tris);
  rest = (float*)malloc((size_t)n * sizeof *rest);
  rest_n = (float*)malloc((size_t)n * sizeof *rest_n);
  positions = (float*)malloc((size_t)frames * (size_t)n * sizeof *positions);
  normals = (float*)malloc((size_t)frames * (size_t)n * sizeof *normals);
  if (!tris || !rest || !rest_n || !positions || !normals) {
    fprintf(stderr, "facesr_play_c: out of memory for %d frames of %d vertices\n", frames, info.num_surface_vertices);
    goto done;
  }
  /* Before the first step the context shows the rest pose. */
  if (failed(facesr_rig_get_triangles(rig, tris, 3 * (int64_t)info.num_surface_triangles), "triangles") ||
      failed(facesr_get_positions(ctx, rest, n), "rest positions") ||
      failed(facesr_get_normals(ctx, rest_n, n), "rest normals"))
    goto done;
  printf("rig: %d blendshapes, %d surface vertices, %d LR nodes; performance: %d frames at %g fps\n",
         info.num_blendshapes, info.num_surface_vertices, info.num_lr_nodes, frames, perf.fps);
  if (play(ctx, &perf, frames, o.async, n, positions, normals) != 0) goto done;

  anim.num_vertices = info.num_surface_vertices;
  anim.num_triangles = info.num_surface_triangles;
  anim.triangles = tris;
  anim.rest_positions = rest;
  anim.rest_normals = rest_n;
  anim.frames = frames;
  anim.positions = positions;
  anim.normals = normals;
  anim.fps = perf.fps;
  anim.metres_per_unit = 0.01;
  anim.name = "face";
  if (gltf_write_animation(o.out, &anim, err, sizeof err) != 0) {
    fprintf(stderr, "facesr_play_c: %s: %s\n", o.out, err);
    goto done;
  }
  printf("wrote %s\n", o.out);
  if (o.dump) {
    if (positions_dump_write(o.dump, positions, (size_t)frames * (size_t)n, err, sizeof err) != 0) {
      fprintf(stderr, "facesr_play_c: %s\n", err);
      goto done;
    }
    printf("wrote %s\n", o.dump);
  }
  rc = 0;
done:
  free(tris);
  free(rest);
  free(rest_n);
  free(positions);
  free(normals);
  performance_free(&perf);
  facesr_context_destroy(ctx);
  facesr_model_free(model);
  facesr_rig_free(rig);
  return rc;
}
