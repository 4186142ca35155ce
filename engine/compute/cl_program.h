#pragma once
#include <string>
#include <type_traits>
#include <vector>

#include "compute/cl_buffer.h"
#include "compute/cl_context.h"

namespace facesr::compute {

// Names of the kernel files compiled into the binary ("smoke.cl", ...).
std::vector<std::string> embedded_kernel_files();
// Source of one kernel file: $FACESR_CL_DIR/<name> when the variable is set,
// else the embedded copy, with each `#include "name"` line replaced by that
// file, recursively. Throws Error listing the known names if one is absent.
std::string load_kernel_source(const std::string& file_name);

// Binds a `__local T*` argument of the given size in bytes.
struct LocalMemory {
  size_t bytes;
};

// One kernel with its argument state; move-only because two owners setting
// arguments on the same cl_kernel would race.
class Kernel {
 public:
  Kernel() = default;
  Kernel(Kernel&&) noexcept = default;
  Kernel& operator=(Kernel&&) noexcept = default;
  Kernel(const Kernel&) = delete;
  Kernel& operator=(const Kernel&) = delete;

  const std::string& name() const { return name_; }
  cl_kernel get() const { return kernel_.get(); }

  // Scalars must match the kernel's parameter size exactly (cl_uint, not
  // size_t); buffers bind their cl_mem; LocalMemory reserves local space.
  template <typename T>
  Kernel& arg(cl_uint index, const T& value) {
    if constexpr (std::is_base_of_v<DeviceBuffer, T>) {
      const cl_mem mem = value.get();
      set_arg_raw(index, sizeof(cl_mem), &mem);
    } else if constexpr (std::is_same_v<T, LocalMemory>) {
      set_arg_raw(index, value.bytes, nullptr);
    } else {
      static_assert(std::is_trivially_copyable_v<T>, "kernel arguments are plain data");
      set_arg_raw(index, sizeof(T), &value);
    }
    return *this;
  }

  // Sets arguments 0..n-1 in order.
  template <typename... Args>
  Kernel& args(const Args&... values) {
    cl_uint index = 0;
    (arg(index++, values), ...);
    return *this;
  }

  // Enqueues a 1D launch without waiting. With local_size > 0 the global
  // size is rounded up to a multiple of it, so kernels must bounds-check
  // their global id. A global size of 0 enqueues nothing.
  void run_1d(size_t global_size, size_t local_size = 0);

  // Largest local size this kernel can launch with on its device.
  size_t max_work_group_size() const;

 private:
  friend class Program;
  void set_arg_raw(cl_uint index, size_t size, const void* value);

  KernelHandle kernel_;
  QueueHandle queue_;
  cl_device_id device_ = nullptr;
  std::string name_;
};

// A built program; cheap to copy (reference counted).
class Program {
 public:
  Program() = default;

  const std::string& name() const { return name_; }  // file names joined by '+'
  const std::string& build_log() const { return log_; }  // warnings of a successful build
  cl_program get() const { return program_.get(); }

  Kernel kernel(const std::string& kernel_name) const;
  std::vector<std::string> kernel_names() const;

 private:
  friend class Context;

  ProgramHandle program_;
  QueueHandle queue_;
  cl_device_id device_ = nullptr;
  std::string name_;
  std::string log_;
};

}  // namespace facesr::compute
