// Stepping (sync and pipelined) and reading the latest frame back.
#include "capi_internal.h"

using namespace facesr;
using namespace facesr::capi;

namespace {

constexpr facesr_status kOk = FACESR_OK;
constexpr int kMaxPending = 2;  // RuntimeContext's pipeline depth

// Copies one surface array of the current frame (`member` of FrameResult).
facesr_status copy_surface(const char* fn, const facesr_context* context, std::vector<float> FrameResult::*member,
                           float* xyz, int64_t count) noexcept {
  if (!context) return null_argument(fn, "context");
  if (!xyz) return null_argument(fn, "xyz");
  const int64_t n = 3 * int64_t(context->runtime->num_vertices());
  if (count != n) return wrong_count(fn, "xyz", count, n, "3 * num_surface_vertices");
  const std::vector<float>& src = context->runtime->result().*member;
  // Only complete frames become the result; check anyway rather than overrun.
  if (int64_t(src.size()) != n) return fail(FACESR_ERROR_INTERNAL, fn, "the current frame has no surface");
  std::memcpy(xyz, src.data(), size_t(n) * sizeof(float));
  return kOk;
}

}  // namespace

extern "C" {

facesr_status facesr_step(facesr_context* context) {
  static const char* fn = "facesr_step";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_SIMULATION, [&] {
    if (const int p = context->runtime->pending())
      return fail(FACESR_ERROR_STATE, fn,
                  std::to_string(p) + " asynchronous frame(s) pending; call facesr_wait until none is left");
    context->runtime->step();
    return kOk;
  });
}

facesr_status facesr_step_async(facesr_context* context) {
  static const char* fn = "facesr_step_async";
  if (!context) return null_argument(fn, "context");
  // Controls are validated as they are set, so an Error here is a control
  // the frame cannot take.
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    if (context->runtime->pending() >= kMaxPending)
      return fail(FACESR_ERROR_STATE, fn,
                  std::to_string(kMaxPending) + " frames are already pending; call facesr_wait first");
    context->runtime->step_async();
    return kOk;
  });
}

facesr_status facesr_wait(facesr_context* context, int64_t* out_frame) {
  static const char* fn = "facesr_wait";
  if (!context) return null_argument(fn, "context");
  return guarded(fn, FACESR_ERROR_SIMULATION, [&] {
    if (context->runtime->pending() == 0)
      return fail(FACESR_ERROR_STATE, fn, "no frame is pending (call facesr_step_async first)");
    const int64_t frame = context->runtime->wait();
    if (out_frame) *out_frame = frame;
    return kOk;
  });
}

facesr_status facesr_pending_frames(const facesr_context* context, int32_t* out_count) {
  static const char* fn = "facesr_pending_frames";
  if (!context) return null_argument(fn, "context");
  if (!out_count) return null_argument(fn, "out_count");
  return guarded(fn, FACESR_ERROR_INTERNAL, [&] {
    *out_count = context->runtime->pending();
    return kOk;
  });
}

facesr_status facesr_get_positions(const facesr_context* context, float* xyz, int64_t count) {
  return copy_surface("facesr_get_positions", context, &FrameResult::positions, xyz, count);
}

facesr_status facesr_get_normals(const facesr_context* context, float* xyz, int64_t count) {
  return copy_surface("facesr_get_normals", context, &FrameResult::normals, xyz, count);
}

facesr_status facesr_get_embedded_positions(const facesr_context* context, float* xyz, int64_t count) {
  return copy_surface("facesr_get_embedded_positions", context, &FrameResult::embedded, xyz, count);
}

static_assert(FACESR_FRAME_CONVERGED == int(facesr::StepStatus::Converged) &&
                  FACESR_FRAME_UNCONVERGED == int(facesr::StepStatus::Unconverged) &&
                  FACESR_FRAME_RECOVERED == int(facesr::StepStatus::Recovered) &&
                  FACESR_FRAME_DIVERGED == int(facesr::StepStatus::Diverged),
              "FACESR_FRAME_* must match facesr::StepStatus");

facesr_status facesr_get_frame_stats(const facesr_context* context, facesr_frame_stats* stats) {
  static const char* fn = "facesr_get_frame_stats";
  if (!context) return null_argument(fn, "context");
  if (!stats) return null_argument(fn, "stats");
  if (const facesr_status s = check_info_size(fn, "facesr_frame_stats", stats->struct_size)) return s;
  const FrameResult& r = context->runtime->result();
  FACESR_PUT(stats, frame, r.frame);
  FACESR_PUT(stats, simulation_ms, r.simulation_ms);
  FACESR_PUT(stats, inference_ms, r.inference_ms);
  FACESR_PUT(stats, total_ms, r.total_ms);
  FACESR_PUT(stats, newton_iterations, r.newton_iterations);
  FACESR_PUT(stats, cg_iterations, r.cg_iterations);
  FACESR_PUT(stats, relative_residual, r.relative_residual);
  FACESR_PUT(stats, simulation_status, int32_t(r.status));
  FACESR_PUT(stats, inverted_tets, r.inverted_tets);
  FACESR_PUT(stats, recoveries, r.recoveries);
  return kOk;
}

}  // extern "C"
