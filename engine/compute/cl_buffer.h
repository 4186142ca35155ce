#pragma once
#include <string>
#include <type_traits>
#include <vector>

#include "compute/cl_context.h"

namespace facesr::compute {

// Untyped device memory. Transfers are blocking and go through the owning
// context's in-order queue, so they are ordered after earlier kernels.
// A zero-byte buffer holds no cl_mem (OpenCL forbids empty allocations) and
// binds as a NULL kernel argument, which keeps empty meshes legal.
class DeviceBuffer {
 public:
  DeviceBuffer() = default;
  DeviceBuffer(const Context& context, size_t bytes, cl_mem_flags flags = CL_MEM_READ_WRITE);

  DeviceBuffer(DeviceBuffer&&) noexcept = default;
  DeviceBuffer& operator=(DeviceBuffer&&) noexcept = default;
  // A copy would alias the same device memory, which is never what is meant.
  DeviceBuffer(const DeviceBuffer&) = delete;
  DeviceBuffer& operator=(const DeviceBuffer&) = delete;

  cl_mem get() const { return mem_.get(); }
  size_t bytes() const { return bytes_; }

  void write_bytes(const void* src, size_t bytes, size_t offset = 0);
  void read_bytes(void* dst, size_t bytes, size_t offset = 0) const;

 private:
  MemHandle mem_;
  QueueHandle queue_;
  size_t bytes_ = 0;
};

// Element-typed view of a DeviceBuffer; T must match the kernel's element
// type bit for bit (float, cl_uint, cl_float4, ...), hence trivially copyable.
template <typename T>
class Buffer : public DeviceBuffer {
  static_assert(std::is_trivially_copyable_v<T>, "device buffers hold plain data");

 public:
  Buffer() = default;
  Buffer(const Context& context, size_t count, cl_mem_flags flags = CL_MEM_READ_WRITE)
      : DeviceBuffer(context, count * sizeof(T), flags) {}
  Buffer(const Context& context, const std::vector<T>& data, cl_mem_flags flags = CL_MEM_READ_WRITE)
      : DeviceBuffer(context, data.size() * sizeof(T), flags) {
    upload(data);
  }

  size_t size() const { return bytes() / sizeof(T); }

  void upload(const T* data, size_t count, size_t first = 0) {
    write_bytes(data, count * sizeof(T), first * sizeof(T));
  }
  void upload(const std::vector<T>& data, size_t first = 0) { upload(data.data(), data.size(), first); }

  void download(T* out, size_t count, size_t first = 0) const {
    read_bytes(out, count * sizeof(T), first * sizeof(T));
  }
  std::vector<T> download() const {
    std::vector<T> out(size());
    download(out.data(), out.size());
    return out;
  }
};

}  // namespace facesr::compute
