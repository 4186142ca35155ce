#include "compute/cl_device.h"

#include <mutex>

#include <CL/cl_ext.h>

#include <algorithm>
#include <cctype>

#include "compute/cl_error.h"

namespace facesr::compute {

namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Drivers pad names with NULs or spaces; strip both so names compare cleanly.
std::string trim(std::string s) {
  auto junk = [](char c) { return c == '\0' || std::isspace(static_cast<unsigned char>(c)); };
  while (!s.empty() && junk(s.back())) s.pop_back();
  size_t start = 0;
  while (start < s.size() && junk(s[start])) ++start;
  return s.substr(start);
}

std::string platform_string(cl_platform_id p, cl_platform_info what, const char* label) {
  size_t size = 0;
  cl_check(clGetPlatformInfo(p, what, 0, nullptr, &size), "clGetPlatformInfo", label);
  std::string s(size, '\0');
  cl_check(clGetPlatformInfo(p, what, size, s.data(), nullptr), "clGetPlatformInfo", label);
  return trim(s);
}

std::string device_string(cl_device_id d, cl_device_info what, const char* label) {
  size_t size = 0;
  cl_check(clGetDeviceInfo(d, what, 0, nullptr, &size), "clGetDeviceInfo", label);
  std::string s(size, '\0');
  cl_check(clGetDeviceInfo(d, what, size, s.data(), nullptr), "clGetDeviceInfo", label);
  return trim(s);
}

template <typename T>
T device_value(cl_device_id d, cl_device_info what, const char* label) {
  T value{};
  cl_check(clGetDeviceInfo(d, what, sizeof(T), &value, nullptr), "clGetDeviceInfo", label);
  return value;
}

DeviceType classify(cl_device_type t) {
  if (t & CL_DEVICE_TYPE_GPU) return DeviceType::Gpu;
  if (t & CL_DEVICE_TYPE_CPU) return DeviceType::Cpu;
  if (t & CL_DEVICE_TYPE_ACCELERATOR) return DeviceType::Accelerator;
  return DeviceType::Other;
}

DeviceInfo query_device(cl_platform_id p, cl_device_id d) {
// The query's own name labels the error if a driver rejects it.
#define FACESR_PLATFORM_STRING(what) platform_string(p, what, #what)
#define FACESR_DEVICE_STRING(what) device_string(d, what, #what)
#define FACESR_DEVICE_VALUE(T, what) device_value<T>(d, what, #what)
  DeviceInfo info;
  info.platform_id = p;
  info.device_id = d;
  info.platform_name = FACESR_PLATFORM_STRING(CL_PLATFORM_NAME);
  info.platform_version = FACESR_PLATFORM_STRING(CL_PLATFORM_VERSION);
  info.device_name = FACESR_DEVICE_STRING(CL_DEVICE_NAME);
  info.vendor = FACESR_DEVICE_STRING(CL_DEVICE_VENDOR);
  info.device_version = FACESR_DEVICE_STRING(CL_DEVICE_VERSION);
  info.driver_version = FACESR_DEVICE_STRING(CL_DRIVER_VERSION);
  info.type = classify(FACESR_DEVICE_VALUE(cl_device_type, CL_DEVICE_TYPE));
  info.compute_units = FACESR_DEVICE_VALUE(cl_uint, CL_DEVICE_MAX_COMPUTE_UNITS);
  info.global_mem_bytes = FACESR_DEVICE_VALUE(cl_ulong, CL_DEVICE_GLOBAL_MEM_SIZE);
  info.max_alloc_bytes = FACESR_DEVICE_VALUE(cl_ulong, CL_DEVICE_MAX_MEM_ALLOC_SIZE);
  info.local_mem_bytes = FACESR_DEVICE_VALUE(cl_ulong, CL_DEVICE_LOCAL_MEM_SIZE);
  info.max_work_group_size = FACESR_DEVICE_VALUE(size_t, CL_DEVICE_MAX_WORK_GROUP_SIZE);
  const std::string ext = FACESR_DEVICE_STRING(CL_DEVICE_EXTENSIONS);
#undef FACESR_PLATFORM_STRING
#undef FACESR_DEVICE_STRING
#undef FACESR_DEVICE_VALUE
  // cl_khr_fp64 is the portable signal; some drivers also report fp64 through
  // a non-zero double FP config without listing the extension. Drivers
  // without fp64 may reject that query, which just means "no".
  cl_device_fp_config fp64 = 0;
  if (clGetDeviceInfo(d, CL_DEVICE_DOUBLE_FP_CONFIG, sizeof(fp64), &fp64, nullptr) != CL_SUCCESS)
    fp64 = 0;
  info.double_support = ext.find("cl_khr_fp64") != std::string::npos || fp64 != 0;
  return info;
}

std::vector<cl_platform_id> platforms() {
  cl_uint count = 0;
  cl_int err = clGetPlatformIDs(0, nullptr, &count);
  // The ICD loader reports "no vendor files" as an error, not as zero platforms.
  if (err == CL_PLATFORM_NOT_FOUND_KHR || count == 0) return {};
  cl_check(err, "clGetPlatformIDs");
  std::vector<cl_platform_id> ids(count);
  cl_check(clGetPlatformIDs(count, ids.data(), nullptr), "clGetPlatformIDs");
  return ids;
}

std::string available_list(const std::vector<DeviceInfo>& devices) {
  std::string s;
  for (const DeviceInfo& d : devices) s += "\n  " + describe(d);
  return s;
}

bool type_matches(DeviceType filter, DeviceType actual) {
  return filter == DeviceType::Any || filter == actual;
}

}  // namespace

const char* device_type_name(DeviceType type) {
  switch (type) {
    case DeviceType::Any: return "any";
    case DeviceType::Cpu: return "cpu";
    case DeviceType::Gpu: return "gpu";
    case DeviceType::Accelerator: return "accelerator";
    case DeviceType::Other: return "other";
  }
  return "other";
}

DeviceType parse_device_type(const std::string& text) {
  const std::string t = lower(text);
  for (DeviceType type : {DeviceType::Any, DeviceType::Cpu, DeviceType::Gpu,
                          DeviceType::Accelerator, DeviceType::Other})
    if (t == device_type_name(type)) return type;
  throw Error("unknown OpenCL device type '" + text + "' (expected any, cpu, gpu, accelerator or other)");
}

std::string describe(const DeviceInfo& d) {
  return "[" + std::to_string(d.index) + "] " + d.platform_name + " / " + d.device_name + " (" +
         device_type_name(d.type) + ", " + std::to_string(d.compute_units) + " CU, " +
         std::to_string(d.global_mem_bytes >> 20) + " MiB)";
}

namespace {

std::vector<DeviceInfo> enumerate_devices() {
  struct Named {
    std::string name;
    cl_platform_id id;
  };
  std::vector<Named> sorted;
  for (cl_platform_id p : platforms())
    sorted.push_back({platform_string(p, CL_PLATFORM_NAME, "CL_PLATFORM_NAME"), p});
  std::stable_sort(sorted.begin(), sorted.end(),
                   [](const Named& a, const Named& b) { return a.name < b.name; });

  std::vector<DeviceInfo> devices;
  for (const Named& p : sorted) {
    cl_uint count = 0;
    if (clGetDeviceIDs(p.id, CL_DEVICE_TYPE_ALL, 0, nullptr, &count) != CL_SUCCESS || count == 0)
      continue;  // see header: a platform without usable devices is skipped
    std::vector<cl_device_id> ids(count);
    cl_check(clGetDeviceIDs(p.id, CL_DEVICE_TYPE_ALL, count, ids.data(), nullptr), "clGetDeviceIDs",
             "platform '" + p.name + "'");
    for (cl_device_id d : ids) {
      devices.push_back(query_device(p.id, d));
      devices.back().index = static_cast<int>(devices.size()) - 1;
    }
  }
  return devices;
}

}  // namespace

std::vector<DeviceInfo> list_devices() {
  // Enumerated once per process, under a lock: PoCL's first platform query
  // is not thread-safe (concurrent first calls crashed or reported no
  // platform), and the device list does not change while a process runs. An
  // empty result is not kept, so a later call may still find a driver.
  static std::mutex mu;
  static std::vector<DeviceInfo> cache;
  std::lock_guard<std::mutex> lock(mu);
  if (cache.empty()) cache = enumerate_devices();
  return cache;
}

DeviceSelector DeviceSelector::parse(const std::string& spec) {
  DeviceSelector sel;
  const std::string s = trim(spec);
  if (s.empty()) return sel;
  const std::string l = lower(s);
  if (l == "any" || l == "cpu" || l == "gpu" || l == "accelerator") {
    sel.type = parse_device_type(l);
  } else if (std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isdigit(c); })) {
    sel.index = std::stoi(s);
  } else {
    sel.name = s;
  }
  return sel;
}

DeviceInfo select_device(const DeviceSelector& sel) {
  const std::vector<DeviceInfo> devices = list_devices();
  if (devices.empty())
    throw Error(
        "no OpenCL platform found: install an OpenCL driver, e.g. `apt install pocl-opencl-icd` "
        "for the CPU (or your GPU vendor's OpenCL ICD), and check /etc/OpenCL/vendors");

  const std::string wanted = lower(sel.name);
  std::vector<const DeviceInfo*> matches;
  for (const DeviceInfo& d : devices) {
    if (!type_matches(sel.type, d.type)) continue;
    if (sel.index && d.index != *sel.index) continue;
    if (!wanted.empty() && lower(d.device_name).find(wanted) == std::string::npos &&
        lower(d.platform_name).find(wanted) == std::string::npos)
      continue;
    matches.push_back(&d);
  }

  if (matches.empty()) {
    std::string what = "type " + std::string(device_type_name(sel.type));
    if (sel.index) what += ", index " + std::to_string(*sel.index);
    if (!sel.name.empty()) what += ", name containing '" + sel.name + "'";
    throw Error("no OpenCL device matches " + what + "; available devices:" + available_list(devices));
  }
  // Default selection prefers a CPU device; explicit criteria take the first match.
  const DeviceInfo* chosen = matches.front();
  if (!sel.index && wanted.empty() && sel.type == DeviceType::Any) {
    for (const DeviceInfo* d : matches)
      if (d->type == DeviceType::Cpu) {
        chosen = d;
        break;
      }
  }
  return sel.parts > 1 ? split_device(*chosen, sel.parts, sel.part) : *chosen;
}

DeviceInfo split_device(const DeviceInfo& device, int parts, int part) {
  require(part >= 0 && part < parts, "device part " + std::to_string(part) + " is out of range [0, " +
                                         std::to_string(parts) + ")");
  const cl_uint per_part = device.compute_units / cl_uint(parts);
  if (per_part == 0) return device;
  const cl_device_partition_property props[] = {CL_DEVICE_PARTITION_EQUALLY, cl_device_partition_property(per_part),
                                                0};
  std::vector<cl_device_id> subs(size_t(parts) + 1);
  cl_uint made = 0;
  if (clCreateSubDevices(device.device_id, props, cl_uint(subs.size()), subs.data(), &made) != CL_SUCCESS)
    return device;  // no partitioning support: the whole device
  std::vector<DeviceHandle> owned;
  for (cl_uint i = 0; i < made; ++i) owned.emplace_back(subs[i]);  // released unless kept below
  if (made < cl_uint(parts)) return device;
  DeviceInfo d = device;
  d.device_id = subs[size_t(part)];
  d.sub_device = owned[size_t(part)];
  d.compute_units = per_part;
  d.device_name += " (part " + std::to_string(part + 1) + " of " + std::to_string(parts) + ")";
  return d;
}

}  // namespace facesr::compute
