#pragma once
#include <string>
#include <vector>

#include "compute/cl_device.h"
#include "compute/cl_error.h"

namespace facesr::compute {

class Program;  // compute/cl_program.h; include it to call build_program

// One device, its cl_context and one in-order command queue. In-order means
// a blocking Buffer::download sees the results of every kernel enqueued
// before it, so callers rarely need explicit events.
class Context {
 public:
  explicit Context(const DeviceSelector& selector = {});
  explicit Context(const DeviceInfo& device);

  Context(Context&&) noexcept = default;
  Context& operator=(Context&&) noexcept = default;
  Context(const Context&) = delete;
  Context& operator=(const Context&) = delete;

  const DeviceInfo& device() const { return device_; }
  cl_context get() const { return context_.get(); }
  cl_command_queue queue() const { return queue_.get(); }

  // Builds kernel files (e.g. {"smoke.cl"}) from the sources embedded at
  // configure time, or from $FACESR_CL_DIR/<name> when that variable is set so
  // kernels can be edited without rebuilding. Files are compiled as one
  // program, in the given order. Throws Error with the build log on failure.
  Program build_program(const std::vector<std::string>& kernel_file_names,
                        const std::string& options = "") const;
  // `name` only labels errors and Program::name().
  Program build_program_from_source(const std::string& name, const std::string& source,
                                    const std::string& options = "") const;

  void finish() const;  // waits for everything enqueued so far

 private:
  Program build(const std::string& name, const std::vector<std::string>& sources,
                const std::string& options) const;

  DeviceInfo device_;
  ContextHandle context_;
  QueueHandle queue_;
};

}  // namespace facesr::compute
