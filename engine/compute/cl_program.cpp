#include "compute/cl_program.h"

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>

// Generated at configure time from cl/*.cl by cmake/EmbedFiles.cmake.
namespace facesr::cl_embedded {
const std::map<std::string, std::string>& embedded_files();
}

namespace facesr::compute {

namespace {

std::string join(const std::vector<std::string>& items, const char* sep) {
  std::string s;
  for (const std::string& item : items) s += (s.empty() ? "" : sep) + item;
  return s;
}

std::string build_log(cl_program program, cl_device_id device) {
  size_t size = 0;
  cl_check(clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, 0, nullptr, &size),
           "clGetProgramBuildInfo", "CL_PROGRAM_BUILD_LOG");
  std::string log(size, '\0');
  cl_check(clGetProgramBuildInfo(program, device, CL_PROGRAM_BUILD_LOG, size, log.data(), nullptr),
           "clGetProgramBuildInfo", "CL_PROGRAM_BUILD_LOG");
  while (!log.empty() && (log.back() == '\0' || log.back() == '\n' || log.back() == ' ')) log.pop_back();
  return log;
}

}  // namespace

std::vector<std::string> embedded_kernel_files() {
  std::vector<std::string> names;
  for (const auto& entry : cl_embedded::embedded_files()) names.push_back(entry.first);
  return names;
}

namespace {

std::string read_kernel_file(const std::string& file_name) {
  const char* dir = std::getenv("FACESR_CL_DIR");
  if (dir && *dir) {
    // No silent fallback to the embedded copy: a developer who set the
    // variable expects to be running the file they are editing.
    const std::string path = std::string(dir) + "/" + file_name;
    std::ifstream in(path, std::ios::binary);
    require(bool(in), "cannot read OpenCL kernel file '" + path + "' (FACESR_CL_DIR is set to '" +
                          dir + "'; unset it to use the kernels built into the binary)");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }
  const auto& files = cl_embedded::embedded_files();
  const auto it = files.find(file_name);
  if (it == files.end())
    throw Error("unknown OpenCL kernel file '" + file_name +
                "'; available: " + join(embedded_kernel_files(), ", "));
  return it->second;
}

// Replaces each `#include "name"` line by that kernel file, recursively: the
// embedded sources have no directory for the OpenCL compiler to search, and
// the material body is included once per value type (cl/fsr_material.h).
std::string expand_includes(const std::string& file_name, const std::string& text, int depth) {
  require(depth < 8, "OpenCL kernel file '" + file_name + "': #include nested too deeply");
  std::istringstream in(text);
  std::ostringstream out;
  std::string line;
  while (std::getline(in, line)) {
    const size_t a = line.find_first_not_of(" \t");
    const std::string directive = "#include \"";
    if (a != std::string::npos && line.compare(a, directive.size(), directive) == 0) {
      const size_t b = a + directive.size(), e = line.find('"', b);
      require(e != std::string::npos, "OpenCL kernel file '" + file_name + "': malformed #include: " + line);
      const std::string name = line.substr(b, e - b);
      const std::string body = expand_includes(name, read_kernel_file(name), depth + 1);
      out << body << (body.empty() || body.back() != '\n' ? "\n" : "");
    } else {
      out << line << "\n";
    }
  }
  return out.str();
}

}  // namespace

std::string load_kernel_source(const std::string& file_name) {
  return expand_includes(file_name, read_kernel_file(file_name), 0);
}

Program Context::build_program(const std::vector<std::string>& kernel_file_names,
                               const std::string& options) const {
  require(!kernel_file_names.empty(), "build_program: no OpenCL kernel files given");
  std::vector<std::string> sources;
  for (const std::string& name : kernel_file_names) sources.push_back(load_kernel_source(name));
  return build(join(kernel_file_names, "+"), sources, options);
}

Program Context::build_program_from_source(const std::string& name, const std::string& source,
                                           const std::string& options) const {
  return build(name, {source}, options);
}

Program Context::build(const std::string& name, const std::vector<std::string>& sources,
                       const std::string& options) const {
  std::vector<const char*> texts;
  std::vector<size_t> lengths;
  for (const std::string& s : sources) {
    texts.push_back(s.data());
    lengths.push_back(s.size());
  }
  cl_int err = CL_SUCCESS;
  Program program;
  program.program_ = ProgramHandle(clCreateProgramWithSource(
      context_.get(), static_cast<cl_uint>(texts.size()), texts.data(), lengths.data(), &err));
  cl_check(err, "clCreateProgramWithSource", name);

  const cl_device_id device = device_.device_id;
  err = clBuildProgram(program.get(), 1, &device, options.c_str(), nullptr, nullptr);
  // The log is the only useful part of a failed build; fetch it before throwing.
  std::string log;
  try {
    log = build_log(program.get(), device);
  } catch (const ClError&) {
    if (err == CL_SUCCESS) throw;
  }
  if (err != CL_SUCCESS)
    throw ClError(err, "OpenCL build of " + name + " failed on device '" + device_.device_name + "' (" +
                           cl_error_name(err) + ", options '" + options + "'). Build log:\n" +
                           (log.empty() ? "(empty)" : log));

  program.queue_ = QueueHandle::retain(queue_.get());
  program.device_ = device;
  program.name_ = name;
  program.log_ = std::move(log);
  return program;
}

Kernel Program::kernel(const std::string& kernel_name) const {
  cl_int err = CL_SUCCESS;
  Kernel k;
  k.kernel_ = KernelHandle(clCreateKernel(program_.get(), kernel_name.c_str(), &err));
  if (err == CL_INVALID_KERNEL_NAME)
    throw ClError(err, "OpenCL program " + name_ + " has no kernel '" + kernel_name +
                           "'; it has: " + join(kernel_names(), ", "));
  cl_check(err, "clCreateKernel", "kernel '" + kernel_name + "' in " + name_);
  k.queue_ = queue_;
  k.device_ = device_;
  k.name_ = kernel_name;
  return k;
}

std::vector<std::string> Program::kernel_names() const {
  size_t size = 0;
  cl_check(clGetProgramInfo(program_.get(), CL_PROGRAM_KERNEL_NAMES, 0, nullptr, &size),
           "clGetProgramInfo", "CL_PROGRAM_KERNEL_NAMES");
  std::string text(size, '\0');
  cl_check(clGetProgramInfo(program_.get(), CL_PROGRAM_KERNEL_NAMES, size, text.data(), nullptr),
           "clGetProgramInfo", "CL_PROGRAM_KERNEL_NAMES");
  std::vector<std::string> names;
  std::istringstream in(text.c_str());
  for (std::string item; std::getline(in, item, ';');)
    if (!item.empty()) names.push_back(item);
  return names;
}

void Kernel::set_arg_raw(cl_uint index, size_t size, const void* value) {
  const cl_int err = clSetKernelArg(kernel_.get(), index, size, value);
  // Messages are built only on failure: this runs for every launch.
  if (err != CL_SUCCESS)
    throw_cl_error(err, "clSetKernelArg",
                   "kernel '" + name_ + "' argument " + std::to_string(index) + ", " +
                       std::to_string(size) + " bytes");
}

void Kernel::run_1d(size_t global_size, size_t local_size) {
  if (global_size == 0) return;  // OpenCL 1.2 rejects empty ranges
  const size_t* local = nullptr;
  if (local_size > 0) {
    global_size = (global_size + local_size - 1) / local_size * local_size;
    local = &local_size;
  }
  const cl_int err = clEnqueueNDRangeKernel(queue_.get(), kernel_.get(), 1, nullptr, &global_size,
                                            local, 0, nullptr, nullptr);
  if (err != CL_SUCCESS)
    throw_cl_error(err, "clEnqueueNDRangeKernel",
                   "kernel '" + name_ + "', global size " + std::to_string(global_size) + ", local size " +
                       (local ? std::to_string(local_size) : std::string("auto")));
}

size_t Kernel::max_work_group_size() const {
  size_t size = 0;
  cl_check(clGetKernelWorkGroupInfo(kernel_.get(), device_, CL_KERNEL_WORK_GROUP_SIZE, sizeof(size), &size,
                                    nullptr),
           "clGetKernelWorkGroupInfo", "kernel '" + name_ + "'");
  return size;
}

}  // namespace facesr::compute
