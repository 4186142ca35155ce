#include "compute/cl_context.h"

namespace facesr::compute {

Context::Context(const DeviceSelector& selector) : Context(select_device(selector)) {}

Context::Context(const DeviceInfo& device) : device_(device) {
  const cl_context_properties props[] = {
      CL_CONTEXT_PLATFORM, reinterpret_cast<cl_context_properties>(device_.platform_id), 0};
  const std::string what = "device '" + device_.device_name + "'";
  cl_int err = CL_SUCCESS;
  context_ = ContextHandle(clCreateContext(props, 1, &device_.device_id, nullptr, nullptr, &err));
  cl_check(err, "clCreateContext", what);
  // clCreateCommandQueue is the 1.2 entry point; the 2.0 replacement is
  // missing from 1.2-only drivers.
  queue_ = QueueHandle(clCreateCommandQueue(context_.get(), device_.device_id, 0, &err));
  cl_check(err, "clCreateCommandQueue", what);
}

void Context::finish() const { cl_check(clFinish(queue_.get()), "clFinish"); }

}  // namespace facesr::compute
