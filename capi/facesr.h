/*
 * facesr.h: the stable C ABI of the facesr runtime.
 *
 * A game steps a cheap muscle simulation on the coarse (LR) lattice and gets
 * back the high-resolution face surface that the trained super-resolution
 * network infers from it (Park et al., "Near-realtime Facial Animation by
 * Deep 3D Simulation Super-Resolution").
 *
 * Conventions
 * - Plain C99. Every symbol starts with facesr_ / FACESR_. No C++ types and no
 *   exceptions cross this boundary.
 * - Objects are opaque handles. The rig and the model are immutable once
 *   loaded (like MuJoCo's mjModel) and may be shared by any number of
 *   contexts on any threads. A context holds the mutable state of one face
 *   (like mjData): use each context from one thread at a time. Different
 *   contexts may be used concurrently from different threads.
 * - Every function that can fail returns a facesr_status (FACESR_OK = 0).
 *   On failure facesr_last_error_message() returns a message naming the
 *   problem; it is per thread and stays valid until the next failing call on
 *   that thread. A failed call leaves every object as it was and usable.
 * - Buffers are owned by the caller and passed with an explicit element
 *   count; a count that differs from the required one is
 *   FACESR_ERROR_BUFFER_SIZE (the message gives the required count).
 * - Definition and information structs start with struct_size, which the
 *   caller sets to sizeof(the struct) as it was compiled. The library reads
 *   and writes only the fields that fit, so callers built against an older,
 *   smaller struct keep working. Use the facesr_default_* functions to fill
 *   definitions. A struct_size below 4 (information structs) or below the
 *   struct's version-1 size (definitions) is FACESR_ERROR_INVALID_ARGUMENT.
 * - Lengths are centimetres, stiffnesses kPa·cm (force per cm), times
 *   milliseconds. Positions are in the rig's rest frame.
 */
#ifndef FACESR_H
#define FACESR_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32)
#if defined(FACESR_BUILDING_LIBRARY)
#define FACESR_API __declspec(dllexport)
#else
#define FACESR_API __declspec(dllimport)
#endif
#else
#define FACESR_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Version of this ABI: incremented on any incompatible change. */
#define FACESR_ABI_VERSION 1

/* ------------------------------------------------------------------ status */

typedef int32_t facesr_status;
#define FACESR_OK 0
#define FACESR_ERROR_NULL_ARGUMENT 1    /* a required pointer or handle is NULL */
#define FACESR_ERROR_INVALID_ARGUMENT 2 /* NaN, out of range, unknown id, bad struct_size */
#define FACESR_ERROR_BUFFER_SIZE 3      /* a buffer's element count is not the required one */
#define FACESR_ERROR_FILE 4             /* missing, unreadable, truncated, corrupt or malformed file */
#define FACESR_ERROR_MISMATCH 5         /* a model trained for another rig */
#define FACESR_ERROR_DEVICE 6           /* no such OpenCL device, or the device failed */
#define FACESR_ERROR_NOT_FOUND 7        /* no blendshape of that name */
#define FACESR_ERROR_STATE 8            /* not possible now (e.g. wait with nothing pending) */
#define FACESR_ERROR_SIMULATION 9       /* the simulation failed on this frame (state kept) */
#define FACESR_ERROR_INTERNAL 10        /* a bug: please report the message */

/* The ABI version the library was built with (FACESR_ABI_VERSION). */
FACESR_API uint32_t facesr_abi_version(void);
/* "facesr 0.1.0". Static storage. */
FACESR_API const char* facesr_version_string(void);
/* Message of the last failed call on this thread ("" if none). */
FACESR_API const char* facesr_last_error_message(void);
/* "FACESR_OK", "FACESR_ERROR_BUFFER_SIZE", ...; "unknown" otherwise. Static storage. */
FACESR_API const char* facesr_status_name(facesr_status status);

/* --------------------------------------------------------------------- rig */

typedef struct facesr_rig facesr_rig;

typedef struct facesr_rig_info {
  uint32_t struct_size;          /* set by the caller: sizeof(facesr_rig_info) */
  int32_t num_blendshapes;       /* ARKit-named controls, in rig order */
  int32_t num_surface_vertices;  /* M: vertices of the output face surface */
  int32_t num_surface_triangles; /* triangles of the output face surface */
  int32_t num_lr_nodes;          /* N: nodes of the LR simulation lattice */
  int32_t num_muscles;
  uint64_t checksum;             /* identifies the rig; a model records the one it was trained on */
  float jaw_pivot[3];            /* a point on the jaw hinge axis (cm): explicit jaw rotations turn about it */
  float jaw_axis[3];             /* unit hinge axis; a positive angle opens the mouth */
} facesr_rig_info;

/* Loads and validates a rig file (from `facesr rig build`). */
FACESR_API facesr_status facesr_rig_load(const char* path, facesr_rig** out_rig);
/* Frees a rig. NULL is ignored. Contexts made from it must be destroyed first. */
FACESR_API void facesr_rig_free(facesr_rig* rig);
FACESR_API facesr_status facesr_rig_get_info(const facesr_rig* rig, facesr_rig_info* info);
/* Blendshape name at index into buf (NUL-terminated, truncated to buf_size - 1 bytes);
   *out_length (if not NULL) receives the full length without the NUL. With
   buf_size 0, buf may be NULL and only the length is returned. */
FACESR_API facesr_status facesr_rig_blendshape_name(const facesr_rig* rig, int32_t index, char* buf,
                                                    int32_t buf_size, int32_t* out_length);
/* Index of a blendshape by exact name, e.g. "jawOpen". */
FACESR_API facesr_status facesr_rig_blendshape_index(const facesr_rig* rig, const char* name, int32_t* out_index);
/* The output surface's triangle index buffer: count must be 3 * num_surface_triangles.
   Counter-clockwise seen from outside. Read it once; it never changes. */
FACESR_API facesr_status facesr_rig_get_triangles(const facesr_rig* rig, int32_t* indices, int64_t count);
/* Rest positions of the output surface: count must be 3 * num_surface_vertices (cm). */
FACESR_API facesr_status facesr_rig_get_rest_positions(const facesr_rig* rig, float* xyz, int64_t count);

/* ------------------------------------------------------------------- model */

typedef struct facesr_model facesr_model;

typedef struct facesr_model_info {
  uint32_t struct_size; /* set by the caller: sizeof(facesr_model_info) */
  uint64_t rig_checksum;
  int32_t num_lr_nodes;
  int32_t num_surface_vertices;
  int32_t num_parameters; /* trainable scalars */
} facesr_model_info;

/* Loads and validates a super-resolution model (from `facesr train`). */
FACESR_API facesr_status facesr_model_load(const char* path, facesr_model** out_model);
FACESR_API void facesr_model_free(facesr_model* model);
FACESR_API facesr_status facesr_model_get_info(const facesr_model* model, facesr_model_info* info);

/* ----------------------------------------------------------------- context */

typedef struct facesr_context facesr_context;

#define FACESR_SOLVER_REALTIME 0 /* at most 3 Newton steps of 60 CG iterations per frame (default) */
#define FACESR_SOLVER_ACCURATE 1 /* Newton to a 1e-3 relative residual (offline quality) */

#define FACESR_PRECISION_AUTO 0   /* float with FACESR_SOLVER_REALTIME, double with FACESR_SOLVER_ACCURATE */
#define FACESR_PRECISION_DOUBLE 1 /* double where the device has it */
#define FACESR_PRECISION_FLOAT 2

#define FACESR_INFERENCE_OPENCL 0 /* the OpenCL inference kernels (default) */
#define FACESR_INFERENCE_CPU 1    /* the plain C++ reference inference (slow; for checks) */

typedef struct facesr_context_def {
  uint32_t struct_size;    /* sizeof(facesr_context_def) */
  int32_t device_index;    /* OpenCL device as listed by `facesr devices`; -1: choose by name or default */
  const char* device_name; /* case-insensitive substring of the device or platform name; NULL or "": default
                              (the first CPU device, PoCL) */
  int32_t solver;          /* FACESR_SOLVER_* */
  int32_t inference;       /* FACESR_INFERENCE_* */
  /* Added after version 1 of this struct (older callers get 0). Nonzero: the
     simulation and the OpenCL inference get half of the device's compute
     units each (OpenCL sub-devices), so that facesr_step_async runs frame t's
     super-resolution and frame t+1's simulation on separate cores. It pays
     only when the two stages cost about the same on half the device: on a
     2-core CPU it measured from 20 % slower to 15 % faster depending on the
     rig and the program (docs/runtime.md). Synchronous steps then run each
     stage on half the device, so leave it 0 unless stepping asynchronously
     and measured.
     Ignored where the device cannot be split (one compute unit; most GPUs). */
  int32_t split_device;
  /* Added after version 2 (older callers get FACESR_PRECISION_AUTO): the LR
     simulation's arithmetic, FACESR_PRECISION_*. The real-time solver's
     tolerances are far above float rounding (on the ICT head float moved the
     surface 0.00003 cm on average against double, 12 % faster); the
     inference is always float. */
  int32_t lr_precision;
} facesr_context_def;

/* A definition with every field at its default; struct_size set. */
FACESR_API facesr_context_def facesr_default_context_def(void);

/* Creates a context for one face. The model must have been trained on this
   rig (else FACESR_ERROR_MISMATCH). def may be NULL for defaults. The rig and
   the model must outlive the context. What depends only on the rig and the
   model is built by the first context on them and shared, read-only, by
   every later one while any of them lives, so later contexts are cheaper;
   contexts may be created on several threads at once. */
FACESR_API facesr_status facesr_context_create(const facesr_rig* rig, const facesr_model* model,
                                               const facesr_context_def* def, facesr_context** out_context);
/* Destroys a context (waiting for its pending asynchronous frames). NULL is ignored. */
FACESR_API void facesr_context_destroy(facesr_context* context);
/* Back to the rest pose: controls cleared, springs and spheres removed, pending frames dropped. */
FACESR_API facesr_status facesr_context_reset(facesr_context* context);

/* ---------------------------------------------------------------- controls */
/* Controls take effect at the next facesr_step / facesr_step_async. */

/* Blendshape weight in [0, 1]. Capture overshoots are tolerated as in the
   Live Link import: values in [-0.1, 1.1] are clamped into [0, 1]; NaN,
   infinities and values beyond that are FACESR_ERROR_INVALID_ARGUMENT. */
FACESR_API facesr_status facesr_set_weight(facesr_context* context, int32_t index, float value);
FACESR_API facesr_status facesr_set_weight_by_name(facesr_context* context, const char* name, float value);
/* All weights at once: count must be num_blendshapes; nothing changes if any value is bad. */
FACESR_API facesr_status facesr_set_weights(facesr_context* context, const float* weights, int64_t count);
/* Explicit rigid jaw motion x' = R x + t: rotation row-major (9 floats, a
   proper rotation), translation in cm (3 floats). Replaces the jaw motion
   that the jaw blendshape weights would give. */
FACESR_API facesr_status facesr_set_jaw_transform(facesr_context* context, const float rotation[9],
                                                  const float translation[3]);
/* The jaw follows the blendshape weights again. */
FACESR_API facesr_status facesr_clear_jaw_transform(facesr_context* context);

/* A spring pulling one surface vertex toward a target point. */
typedef struct facesr_spring_def {
  uint32_t struct_size; /* sizeof(facesr_spring_def) */
  int32_t vertex;       /* output-surface vertex index */
  float target[3];      /* cm, rest frame */
  float stiffness;      /* kPa·cm, > 0 */
} facesr_spring_def;

/* A kinematic sphere pushing the face away (penalty). */
typedef struct facesr_sphere_def {
  uint32_t struct_size; /* sizeof(facesr_sphere_def) */
  float centre[3];      /* cm, rest frame */
  float radius;         /* cm, > 0 */
  float stiffness;      /* kPa·cm, > 0 */
} facesr_sphere_def;

/* Spring: vertex -1 (must be set), target (0, 0, 0), stiffness 100.
   Sphere: centre (0, 0, 0), radius 1 cm, stiffness 200. */
FACESR_API facesr_spring_def facesr_default_spring_def(void);
FACESR_API facesr_sphere_def facesr_default_sphere_def(void);

/* Ids are positive and unique within a context (never reused). */
FACESR_API facesr_status facesr_add_spring(facesr_context* context, const facesr_spring_def* def, int32_t* out_id);
FACESR_API facesr_status facesr_move_spring(facesr_context* context, int32_t id, const float target[3]);
FACESR_API facesr_status facesr_remove_spring(facesr_context* context, int32_t id);
FACESR_API facesr_status facesr_add_sphere(facesr_context* context, const facesr_sphere_def* def, int32_t* out_id);
FACESR_API facesr_status facesr_move_sphere(facesr_context* context, int32_t id, const float centre[3]);
FACESR_API facesr_status facesr_remove_sphere(facesr_context* context, int32_t id);

/* ---------------------------------------------------------------- stepping */

/* Simulates one frame with the current controls and super-resolves it; the
   results are readable when it returns. Not allowed while asynchronous
   frames are pending (FACESR_ERROR_STATE). */
FACESR_API facesr_status facesr_step(facesr_context* context);

/* Queues one frame with the current controls (copied) and returns at once.
   The context simulates frame t+1 while it super-resolves frame t, so a game
   that calls step_async then wait every tick sees each frame one tick late
   at a higher frame rate. At most 2 frames may be pending
   (FACESR_ERROR_STATE beyond that). The surfaces equal those of facesr_step
   with the same controls. */
FACESR_API facesr_status facesr_step_async(facesr_context* context);

/* Blocks until the oldest pending frame is done and makes its results the
   readable ones; *out_frame (if not NULL) receives its frame number.
   FACESR_ERROR_STATE when nothing is pending. A frame that failed returns
   its error here. */
FACESR_API facesr_status facesr_wait(facesr_context* context, int64_t* out_frame);

/* Frames still pending (queued by step_async and not yet returned by wait). */
FACESR_API facesr_status facesr_pending_frames(const facesr_context* context, int32_t* out_count);

/* ---------------------------------------------------------------- read-back */
/* Of the latest readable frame (before the first step: the rest pose). */

/* Super-resolved surface positions: count must be 3 * num_surface_vertices (cm). */
FACESR_API facesr_status facesr_get_positions(const facesr_context* context, float* xyz, int64_t count);
/* Unit area-weighted vertex normals of that surface: count 3 * num_surface_vertices. */
FACESR_API facesr_status facesr_get_normals(const facesr_context* context, float* xyz, int64_t count);
/* The same surface carried by the LR lattice's embedding alone (the
   "embedded" result, without super-resolution): count 3 * num_surface_vertices. */
FACESR_API facesr_status facesr_get_embedded_positions(const facesr_context* context, float* xyz, int64_t count);

typedef struct facesr_frame_stats {
  uint32_t struct_size;  /* sizeof(facesr_frame_stats) */
  int64_t frame;         /* 0, 1, ... in stepping order; -1 before the first step */
  float simulation_ms;   /* LR simulation of this frame */
  float inference_ms;    /* super-resolution of this frame */
  float total_ms;        /* wall time from its start to its results (sync), or submit to done (async) */
  int32_t newton_iterations;
  int32_t cg_iterations;
  float relative_residual; /* of the LR solve */
  /* Added after version 1 of this struct (older callers do not get them).
     The LR solve's outcome, FACESR_FRAME_*. FACESR_FRAME_DIVERGED: the solve
     broke down (non-finite forces, a residual above the rest pose's, or a
     burst of inverted tets) and every recovery failed (a restart from the
     last good state, control sub-steps, the accurate preset); the positions,
     normals and embedded positions returned are then the last good frame's,
     never a broken surface. A game may keep stepping: the next frame starts
     from that good state. */
  int32_t simulation_status;
  int32_t inverted_tets; /* LR tets inverted (det F <= 0) in the solve that was kept */
  int32_t recoveries;    /* extra solves the recovery ran on this frame (0 normally) */
} facesr_frame_stats;

#define FACESR_FRAME_CONVERGED 0   /* reached the solver's tolerance */
#define FACESR_FRAME_UNCONVERGED 1 /* stopped at the iteration cap above tolerance (normal for the real-time preset) */
#define FACESR_FRAME_RECOVERED 2   /* diverged at first, solved by the recovery */
#define FACESR_FRAME_DIVERGED 3    /* recovery failed: the last good surface is returned */

FACESR_API facesr_status facesr_get_frame_stats(const facesr_context* context, facesr_frame_stats* stats);

#ifdef __cplusplus
}
#endif

#endif /* FACESR_H */
