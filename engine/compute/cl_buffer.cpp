#include "compute/cl_buffer.h"

namespace facesr::compute {

namespace {

void check_range(size_t offset, size_t bytes, size_t size, const char* op) {
  require(offset <= size && bytes <= size - offset,
          std::string("OpenCL buffer ") + op + " out of range: " + std::to_string(bytes) +
              " bytes at offset " + std::to_string(offset) + " in a buffer of " + std::to_string(size) +
              " bytes");
}

}  // namespace

DeviceBuffer::DeviceBuffer(const Context& context, size_t bytes, cl_mem_flags flags)
    : queue_(QueueHandle::retain(context.queue())), bytes_(bytes) {
  if (bytes == 0) return;
  cl_int err = CL_SUCCESS;
  mem_ = MemHandle(clCreateBuffer(context.get(), flags, bytes, nullptr, &err));
  cl_check(err, "clCreateBuffer",
           std::to_string(bytes) + " bytes on '" + context.device().device_name + "'");
}

void DeviceBuffer::write_bytes(const void* src, size_t bytes, size_t offset) {
  check_range(offset, bytes, bytes_, "upload");
  if (bytes == 0) return;
  cl_check(clEnqueueWriteBuffer(queue_.get(), mem_.get(), CL_TRUE, offset, bytes, src, 0, nullptr, nullptr),
           "clEnqueueWriteBuffer");
}

void DeviceBuffer::read_bytes(void* dst, size_t bytes, size_t offset) const {
  check_range(offset, bytes, bytes_, "download");
  if (bytes == 0) return;
  cl_check(clEnqueueReadBuffer(queue_.get(), mem_.get(), CL_TRUE, offset, bytes, dst, 0, nullptr, nullptr),
           "clEnqueueReadBuffer");
}

}  // namespace facesr::compute
