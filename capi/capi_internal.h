#pragma once
// Internals shared by the C ABI's translation units: the handle types, the
// exception-to-status boundary, and the struct_size rules.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <new>
#include <string>
#include <type_traits>
#include <unordered_map>
#include <vector>

#include "core/error.h"
#include "facesr.h"
#include "rig/rig.h"
#include "runtime/runtime_context.h"
#include "runtime/runtime_model.h"
#include "sr/sr_model.h"

namespace facesr::capi {

// What a rig handle owns. Contexts hold it too, so freeing the rig handle
// while contexts still use it is safe (the header asks callers not to).
struct LoadedRig {
  std::shared_ptr<const Rig> rig;
  uint64_t checksum = 0;
  std::unordered_map<std::string, int32_t> index;  // blendshape name -> rig order
};

// A model handle's compiled runtime models, one per rig it is used with: the
// first context on a rig and model compiles it, later ones share it. Held
// weakly, so it lives as long as some context uses it and a rig freed by
// the caller is not kept alive by the model.
class CompiledModels {
 public:
  std::shared_ptr<const RuntimeModel> get(const std::shared_ptr<const LoadedRig>& rig,
                                          const std::shared_ptr<const SrModel>& model);

 private:
  struct Entry {
    std::weak_ptr<const LoadedRig> rig;
    std::weak_ptr<const RuntimeModel> compiled;
  };
  std::mutex mu_;
  std::vector<Entry> entries_;
};

}  // namespace facesr::capi

struct facesr_rig {
  std::shared_ptr<const facesr::capi::LoadedRig> loaded;
};

struct facesr_model {
  std::shared_ptr<const facesr::SrModel> model;
  int64_t num_parameters = 0;
  // Contexts on a const model handle share what they compile: the cache is
  // behind a pointer, and locked.
  std::unique_ptr<facesr::capi::CompiledModels> compiled = std::make_unique<facesr::capi::CompiledModels>();
};

struct facesr_context {
  std::shared_ptr<const facesr::capi::LoadedRig> loaded;
  std::shared_ptr<const facesr::SrModel> model;
  std::unique_ptr<facesr::RuntimeContext> runtime;
};

namespace facesr::capi {

// Records "<fn>: <message>" as this thread's last error and returns status.
// Never throws: it runs inside catch handlers at the boundary.
facesr_status fail(facesr_status status, const char* fn, const std::string& message) noexcept;

facesr_status null_argument(const char* fn, const char* what) noexcept;

// BUFFER_SIZE naming the buffer, what it holds and the count it needs.
facesr_status wrong_count(const char* fn, const char* what, int64_t given, int64_t required, const char* rule) noexcept;

// Runs body() (which returns a status). A facesr::Error becomes `on_error`
// with its message; anything else is FACESR_ERROR_INTERNAL. Nothing escapes:
// unwinding into C is undefined behaviour.
template <class F>
facesr_status guarded(const char* fn, facesr_status on_error, F&& body) noexcept {
  try {
    return body();
  } catch (const Error& e) {
    return fail(on_error, fn, e.what());
  } catch (const std::bad_alloc&) {
    return fail(FACESR_ERROR_INTERNAL, fn, "out of memory");
  } catch (const std::exception& e) {
    return fail(FACESR_ERROR_INTERNAL, fn, std::string("unexpected error: ") + e.what());
  } catch (...) {
    return fail(FACESR_ERROR_INTERNAL, fn, "unexpected non-standard exception");
  }
}

// Information structs: a caller built against an older header passes a
// smaller struct_size, so a field is written only when it lies wholly inside
// it (the caller's memory may end right there).
template <class S, class T>
void put_field(S* s, size_t offset, const T& value) {
  if (offset + sizeof(T) <= s->struct_size) std::memcpy(reinterpret_cast<char*>(s) + offset, &value, sizeof(T));
}
#define FACESR_PUT(s, field, value) \
  ::facesr::capi::put_field((s), offsetof(std::remove_pointer_t<decltype(s)>, field), decltype((s)->field)(value))

facesr_status def_too_small(const char* fn, const char* type, uint32_t struct_size, size_t v1_size) noexcept;

// struct_size must at least cover the struct_size field itself.
facesr_status check_info_size(const char* fn, const char* type, uint32_t struct_size) noexcept;

// Definitions: fields beyond struct_size keep their defaults (for callers of
// an older header), bytes beyond sizeof(S) are a newer caller's and are
// ignored. Anything smaller than version 1 of the struct is a caller bug.
template <class S>
facesr_status read_def(const char* fn, const char* type, const S* in, size_t v1_size, S& out) noexcept {
  if (in->struct_size < v1_size) return def_too_small(fn, type, in->struct_size, v1_size);
  const uint32_t size = std::min<uint32_t>(in->struct_size, uint32_t(sizeof(S)));
  std::memcpy(static_cast<void*>(&out), in, size);
  out.struct_size = uint32_t(sizeof(S));
  return FACESR_OK;
}

// Sizes of the version-1 definitions: up to the end of their last version-1
// field, which stays put as later versions append fields. They are the
// smallest struct_size a caller can legitimately pass.
constexpr size_t kContextDefV1 = offsetof(facesr_context_def, inference) + sizeof(int32_t);
constexpr size_t kSpringDefV1 = offsetof(facesr_spring_def, stiffness) + sizeof(float);
constexpr size_t kSphereDefV1 = offsetof(facesr_sphere_def, stiffness) + sizeof(float);

}  // namespace facesr::capi
