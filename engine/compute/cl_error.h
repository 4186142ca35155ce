#pragma once
#include <CL/cl.h>

#include <string>
#include <utility>

#include "core/error.h"

namespace facesr::compute {

// An OpenCL call failed. The message names the call, the symbolic error code
// and what was being done, so a user report is actionable without a debugger.
class ClError : public Error {
 public:
  ClError(cl_int code, const std::string& message) : Error(message), code_(code) {}
  cl_int code() const { return code_; }

 private:
  cl_int code_;
};

// "CL_INVALID_KERNEL_ARGS" for -52; "CL_UNKNOWN_ERROR" for codes outside the
// OpenCL 1.2 set and its common extensions.
const char* cl_error_name(cl_int code);

[[noreturn]] void throw_cl_error(cl_int code, const std::string& call, const std::string& what);

// Every cl* return code goes through here. `what` is optional context such as
// "kernel 'saxpy' argument 2".
inline void cl_check(cl_int code, const char* call, const std::string& what = {}) {
  if (code != CL_SUCCESS) throw_cl_error(code, call, what);
}

// Reference-counted owner of one OpenCL object. Copies retain, destruction
// releases, so a Buffer or Kernel keeps its queue alive even if the Context
// that made it is destroyed first.
template <typename T, cl_int(CL_API_CALL* Retain)(T), cl_int(CL_API_CALL* Release)(T)>
class ClHandle {
 public:
  ClHandle() = default;
  explicit ClHandle(T adopted) : h_(adopted) {}  // takes over one reference
  // Shares an object owned elsewhere (e.g. the Context's queue).
  static ClHandle retain(T borrowed) {
    if (borrowed) cl_check(Retain(borrowed), "clRetain*");
    return ClHandle(borrowed);
  }
  ClHandle(const ClHandle& o) : h_(o.h_) {
    if (h_) Retain(h_);
  }
  ClHandle(ClHandle&& o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  ClHandle& operator=(ClHandle o) noexcept {
    std::swap(h_, o.h_);
    return *this;
  }
  ~ClHandle() {
    // Release cannot usefully fail here and destructors must not throw.
    if (h_) Release(h_);
  }
  T get() const { return h_; }
  explicit operator bool() const { return h_ != nullptr; }

 private:
  T h_ = nullptr;
};

using ContextHandle = ClHandle<cl_context, clRetainContext, clReleaseContext>;
using DeviceHandle = ClHandle<cl_device_id, clRetainDevice, clReleaseDevice>;  // sub-devices only
using QueueHandle = ClHandle<cl_command_queue, clRetainCommandQueue, clReleaseCommandQueue>;
using MemHandle = ClHandle<cl_mem, clRetainMemObject, clReleaseMemObject>;
using ProgramHandle = ClHandle<cl_program, clRetainProgram, clReleaseProgram>;
using KernelHandle = ClHandle<cl_kernel, clRetainKernel, clReleaseKernel>;

}  // namespace facesr::compute
