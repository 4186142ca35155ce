// Contexts: creation (with the status of whatever stands in the way), reset,
// and the per-frame controls.
#include "capi_internal.h"
#include "compute/cl_device.h"

using namespace facesr;
using namespace facesr::capi;

namespace {

constexpr facesr_status kOk = FACESR_OK;

// Defaults of the spring and sphere definitions: the stiffnesses that visibly
// pull a lip corner and push a cheek on the realtime solver.
constexpr float kSpringStiffness = 100, kSphereRadius = 1, kSphereStiffness = 200;

Vec3 vec3(const float* v) { return Vec3(double(v[0]), double(v[1]), double(v[2])); }

compute::DeviceSelector device_selector(const facesr_context_def& d) {
  compute::DeviceSelector sel;
  if (d.device_index >= 0) sel.index = d.device_index;
  if (d.device_name) sel.name = d.device_name;
  return sel;
}

facesr_status create(const facesr_rig* rig, const facesr_model* model, const facesr_context_def& d,
                     facesr_context** out) {
  static const char* fn = "facesr_context_create";
  const LoadedRig& l = *rig->loaded;
  if (d.solver != FACESR_SOLVER_REALTIME && d.solver != FACESR_SOLVER_ACCURATE)
    return fail(
        FACESR_ERROR_INVALID_ARGUMENT, fn,
        "solver " + std::to_string(d.solver) + " is not FACESR_SOLVER_REALTIME (0) or FACESR_SOLVER_ACCURATE (1)");
  if (d.inference != FACESR_INFERENCE_OPENCL && d.inference != FACESR_INFERENCE_CPU)
    return fail(
        FACESR_ERROR_INVALID_ARGUMENT, fn,
        "inference " + std::to_string(d.inference) + " is not FACESR_INFERENCE_OPENCL (0) or FACESR_INFERENCE_CPU (1)");
  if (d.lr_precision != FACESR_PRECISION_AUTO && d.lr_precision != FACESR_PRECISION_DOUBLE &&
      d.lr_precision != FACESR_PRECISION_FLOAT)
    return fail(FACESR_ERROR_INVALID_ARGUMENT, fn,
                "lr_precision " + std::to_string(d.lr_precision) +
                    " is not FACESR_PRECISION_AUTO (0), FACESR_PRECISION_DOUBLE (1) or FACESR_PRECISION_FLOAT (2)");
  if (d.device_index < -1)
    return fail(FACESR_ERROR_INVALID_ARGUMENT, fn,
                "device_index " + std::to_string(d.device_index) + " is negative (use -1 for the default)");

  const facesr_status mismatch = guarded(fn, FACESR_ERROR_MISMATCH, [&] {
    require_model_matches_rig(*model->model, l.checksum, int(l.rig->lr.mesh.X.rows()), l.rig->num_surface_vertices(),
                              "the model", "rig '" + l.rig->name + "'");
    return kOk;
  });
  if (mismatch) return mismatch;

  RuntimeOptions opt;
  opt.device = device_selector(d);
  opt.solver = d.solver == FACESR_SOLVER_ACCURATE ? SolverOptions{} : realtime_solver();
  opt.cpu_inference = d.inference == FACESR_INFERENCE_CPU;
  opt.split_device = d.split_device != 0;
  opt.lr_single_precision = d.lr_precision == FACESR_PRECISION_FLOAT ||
                            (d.lr_precision == FACESR_PRECISION_AUTO && d.solver == FACESR_SOLVER_REALTIME);
  // Past the checks above, what can fail is opening the device, building its
  // kernels or allocating on it.
  return guarded(fn, FACESR_ERROR_DEVICE, [&] {
    compute::select_device(opt.device);
    auto c = std::make_unique<facesr_context>();
    c->loaded = rig->loaded;
    c->model = model->model;
    c->runtime = std::make_unique<RuntimeContext>(model->compiled->get(rig->loaded, model->model), opt);
    *out = c.release();
    return kOk;
  });
}

}  // namespace

extern "C" {

facesr_context_def facesr_default_context_def(void) {
  facesr_context_def d{};
  d.struct_size = sizeof d;
  d.device_index = -1;
  d.device_name = nullptr;
  d.solver = FACESR_SOLVER_REALTIME;
  d.inference = FACESR_INFERENCE_OPENCL;
  d.split_device = 0;
  d.lr_precision = FACESR_PRECISION_AUTO;
  return d;
}

facesr_spring_def facesr_default_spring_def(void) {
  facesr_spring_def d{};
  d.struct_size = sizeof d;
  d.vertex = -1;
  d.stiffness = kSpringStiffness;
  return d;
}

facesr_sphere_def facesr_default_sphere_def(void) {
  facesr_sphere_def d{};
  d.struct_size = sizeof d;
  d.radius = kSphereRadius;
  d.stiffness = kSphereStiffness;
  return d;
}

facesr_status facesr_context_create(const facesr_rig* rig, const facesr_model* model, const facesr_context_def* def,
                                    facesr_context** out_context) {
  static const char* fn = "facesr_context_create";
  if (!out_context) return null_argument(fn, "out_context");
  *out_context = nullptr;
  if (!rig) return null_argument(fn, "rig");
  if (!model) return null_argument(fn, "model");
  facesr_context_def d = facesr_default_context_def();
  if (def)
    if (const facesr_status s = read_def(fn, "facesr_context_def", def, kContextDefV1, d)) return s;
  return guarded(fn, FACESR_ERROR_INTERNAL, [&] { return create(rig, model, d, out_context); });
}

void facesr_context_destroy(facesr_context* context) { delete context; }

facesr_status facesr_context_reset(facesr_context* context) {
  static const char* fn = "facesr_context_reset";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_DEVICE, [&] {
    context->runtime->reset();
    return kOk;
  });
}

facesr_status facesr_set_weight(facesr_context* context, int32_t index, float value) {
  static const char* fn = "facesr_set_weight";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->set_weight(index, value);
    return kOk;
  });
}

facesr_status facesr_set_weight_by_name(facesr_context* context, const char* name, float value) {
  static const char* fn = "facesr_set_weight_by_name";
  if (!context) return null_argument(fn, "context");
  if (!name) return null_argument(fn, "name");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    const LoadedRig& l = *context->loaded;
    const auto it = l.index.find(name);
    if (it == l.index.end())
      return fail(FACESR_ERROR_NOT_FOUND, fn,
                  "no blendshape named '" + std::string(name) + "' in rig '" + l.rig->name +
                      "' (names are case-sensitive ARKit names)");
    context->runtime->set_weight(it->second, value);
    return kOk;
  });
}

facesr_status facesr_set_weights(facesr_context* context, const float* weights, int64_t count) {
  static const char* fn = "facesr_set_weights";
  if (!context) return null_argument(fn, "context");
  if (!weights) return null_argument(fn, "weights");
  const int64_t n = context->runtime->num_weights();
  if (count != n) return wrong_count(fn, "weights", count, n, "num_blendshapes");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->set_weights(std::vector<float>(weights, weights + n));
    return kOk;
  });
}

facesr_status facesr_set_jaw_transform(facesr_context* context, const float rotation[9], const float translation[3]) {
  static const char* fn = "facesr_set_jaw_transform";
  if (!context) return null_argument(fn, "context");
  if (!rotation) return null_argument(fn, "rotation");
  if (!translation) return null_argument(fn, "translation");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    Mat3 R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R(r, c) = double(rotation[3 * r + c]);
    context->runtime->set_jaw(R, vec3(translation));
    return kOk;
  });
}

facesr_status facesr_clear_jaw_transform(facesr_context* context) {
  static const char* fn = "facesr_clear_jaw_transform";
  if (!context) return null_argument(fn, "context");
  context->runtime->clear_jaw();
  return kOk;
}

facesr_status facesr_add_spring(facesr_context* context, const facesr_spring_def* def, int32_t* out_id) {
  static const char* fn = "facesr_add_spring";
  if (!out_id) return null_argument(fn, "out_id");
  *out_id = 0;
  if (!context) return null_argument(fn, "context");
  if (!def) return null_argument(fn, "def");
  facesr_spring_def d = facesr_default_spring_def();
  if (const facesr_status s = read_def(fn, "facesr_spring_def", def, kSpringDefV1, d)) return s;
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    *out_id = context->runtime->add_spring(d.vertex, vec3(d.target), double(d.stiffness));
    return kOk;
  });
}

facesr_status facesr_move_spring(facesr_context* context, int32_t id, const float target[3]) {
  static const char* fn = "facesr_move_spring";
  if (!context) return null_argument(fn, "context");
  if (!target) return null_argument(fn, "target");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->move_spring(id, vec3(target));
    return kOk;
  });
}

facesr_status facesr_remove_spring(facesr_context* context, int32_t id) {
  static const char* fn = "facesr_remove_spring";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->remove_spring(id);
    return kOk;
  });
}

facesr_status facesr_add_sphere(facesr_context* context, const facesr_sphere_def* def, int32_t* out_id) {
  static const char* fn = "facesr_add_sphere";
  if (!out_id) return null_argument(fn, "out_id");
  *out_id = 0;
  if (!context) return null_argument(fn, "context");
  if (!def) return null_argument(fn, "def");
  facesr_sphere_def d = facesr_default_sphere_def();
  if (const facesr_status s = read_def(fn, "facesr_sphere_def", def, kSphereDefV1, d)) return s;
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    *out_id = context->runtime->add_sphere(vec3(d.centre), double(d.radius), double(d.stiffness));
    return kOk;
  });
}

facesr_status facesr_move_sphere(facesr_context* context, int32_t id, const float centre[3]) {
  static const char* fn = "facesr_move_sphere";
  if (!context) return null_argument(fn, "context");
  if (!centre) return null_argument(fn, "centre");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->move_sphere(id, vec3(centre));
    return kOk;
  });
}

facesr_status facesr_remove_sphere(facesr_context* context, int32_t id) {
  static const char* fn = "facesr_remove_sphere";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    context->runtime->remove_sphere(id);
    return kOk;
  });
}

}  // extern "C"
