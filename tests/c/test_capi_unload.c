/* A host that loads libfacesr.so at run time and unloads it again (Mono
   unloads DllImport libraries at shutdown; game editors reload plugins).
   Stepping with CPU inference leaves OpenMP worker threads parked in libgomp,
   and the OpenCL driver keeps its own threads: if dlclose unmapped the library
   and its dependencies, those threads would run unmapped code (the csharp
   sample crashed that way, intermittently, at exit). The library is linked
   with -z nodelete, so it must still be resident after dlclose, and the
   process must outlive its threads' next wake-up.
     facesr_capi_unload_test LIB.so p.rig p.fsm */
#define _POSIX_C_SOURCE 200809L
#include <dlfcn.h>
#include <stdio.h>
#include <time.h>

#include "facesr.h"

typedef facesr_status (*rig_load_fn)(const char*, facesr_rig**);
typedef void (*rig_free_fn)(facesr_rig*);
typedef facesr_status (*model_load_fn)(const char*, facesr_model**);
typedef void (*model_free_fn)(facesr_model*);
typedef facesr_context_def (*default_def_fn)(void);
typedef facesr_status (*create_fn)(const facesr_rig*, const facesr_model*, const facesr_context_def*,
                                   facesr_context**);
typedef void (*destroy_fn)(facesr_context*);
typedef facesr_status (*set_weight_fn)(facesr_context*, const char*, float);
typedef facesr_status (*step_fn)(facesr_context*);

static int fail(const char* what) {
  fprintf(stderr, "test_capi_unload: %s\n", what);
  return 1;
}

static void* sym(void* lib, const char* name) {
  void* p = dlsym(lib, name);
  if (!p) fprintf(stderr, "test_capi_unload: missing symbol %s\n", name);
  return p;
}

int main(int argc, char** argv) {
  if (argc != 4) return fail("usage: facesr_capi_unload_test LIB.so p.rig p.fsm");
  void* lib = dlopen(argv[1], RTLD_NOW | RTLD_LOCAL);
  if (!lib) return fail(dlerror());

  /* ISO C has no cast from void* to a function pointer (-Wpedantic): the
     symbols go through unions instead. */
  union { void* p; rig_load_fn f; } rig_load = {sym(lib, "facesr_rig_load")};
  union { void* p; rig_free_fn f; } rig_free = {sym(lib, "facesr_rig_free")};
  union { void* p; model_load_fn f; } model_load = {sym(lib, "facesr_model_load")};
  union { void* p; model_free_fn f; } model_free = {sym(lib, "facesr_model_free")};
  union { void* p; default_def_fn f; } default_def = {sym(lib, "facesr_default_context_def")};
  union { void* p; create_fn f; } create = {sym(lib, "facesr_context_create")};
  union { void* p; destroy_fn f; } destroy = {sym(lib, "facesr_context_destroy")};
  union { void* p; set_weight_fn f; } set_weight = {sym(lib, "facesr_set_weight_by_name")};
  union { void* p; step_fn f; } step = {sym(lib, "facesr_step")};
  if (!rig_load.p || !rig_free.p || !model_load.p || !model_free.p || !default_def.p || !create.p ||
      !destroy.p || !set_weight.p || !step.p)
    return 1;

  facesr_rig* rig = NULL;
  facesr_model* model = NULL;
  facesr_context* c = NULL;
  if (rig_load.f(argv[2], &rig) != FACESR_OK) return fail("cannot load the rig");
  if (model_load.f(argv[3], &model) != FACESR_OK) return fail("cannot load the model");
  facesr_context_def def = default_def.f();
  def.inference = FACESR_INFERENCE_CPU; /* the OpenMP reference: it starts libgomp's thread pool */
  if (create.f(rig, model, &def, &c) != FACESR_OK) return fail("cannot create a context");
  for (int i = 0; i < 3; ++i) {
    if (set_weight.f(c, "jawOpen", 0.2f * (float)(i + 1)) != FACESR_OK) return fail("set_weight failed");
    if (step.f(c) != FACESR_OK) return fail("step failed");
  }
  destroy.f(c);
  model_free.f(model);
  rig_free.f(rig);

  if (dlclose(lib) != 0) return fail(dlerror());
  if (!dlopen(argv[1], RTLD_NOW | RTLD_NOLOAD))
    return fail("libfacesr was unmapped by dlclose while its worker threads live on (link it with -z nodelete)");
  /* Let parked worker threads spin and wake; with the library gone this crashed. */
  struct timespec pause = {0, 200000000};
  nanosleep(&pause, NULL);
  printf("libfacesr stays resident after dlclose; worker threads outlived it safely\n");
  return 0;
}
