#pragma once
#include <CL/cl.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "compute/cl_error.h"

namespace facesr::compute {

enum class DeviceType { Any, Cpu, Gpu, Accelerator, Other };

// "any", "cpu", "gpu", "accelerator", "other".
const char* device_type_name(DeviceType type);
// Case-insensitive inverse of device_type_name; throws Error on anything else.
DeviceType parse_device_type(const std::string& text);

// What `facesr devices --json` reports, plus the raw ids needed to open it.
struct DeviceInfo {
  int index = -1;  // position in list_devices(); what DeviceSelector::index refers to
  std::string platform_name;
  std::string platform_version;
  std::string device_name;
  std::string vendor;
  std::string device_version;
  std::string driver_version;
  DeviceType type = DeviceType::Other;
  uint32_t compute_units = 0;
  uint64_t global_mem_bytes = 0;
  uint64_t max_alloc_bytes = 0;
  uint64_t local_mem_bytes = 0;
  size_t max_work_group_size = 0;
  bool double_support = false;
  cl_platform_id platform_id = nullptr;
  cl_device_id device_id = nullptr;
  // Set for a sub-device (DeviceSelector::parts): keeps it alive while any
  // copy of this info, or a Context made from it, exists.
  DeviceHandle sub_device;
};

// One line for logs: "[0] Portable Computing Language / cpu-haswell (cpu, 8 CU)".
std::string describe(const DeviceInfo& device);

// Every device of every platform. Platforms are ordered by name (the ICD
// loader's order depends on directory listing order), devices in driver order
// within a platform, so indices are stable on a given machine. Empty when no
// OpenCL platform is installed; platforms whose driver fails to report devices
// are skipped so that one broken ICD does not hide working ones.
std::vector<DeviceInfo> list_devices();

// How to choose a device. With neither index nor name, the first CPU device
// is taken (PoCL: deterministic and always present in CI), falling back to the
// first device of any type. `type` filters every mode.
struct DeviceSelector {
  std::optional<int> index;  // global index as in list_devices()
  std::string name;          // case-insensitive substring of device or platform name
  DeviceType type = DeviceType::Any;
  // parts > 1: split the chosen device into that many sub-devices with equal
  // compute units (clCreateSubDevices, CL_DEVICE_PARTITION_EQUALLY) and take
  // number `part` (0-based). A device that cannot be split that way (one
  // compute unit, or no support: most GPUs) is used whole.
  int parts = 0;
  int part = 0;

  // CLI syntax: "" (default), "cpu"/"gpu"/"any", a number (index), or a name.
  static DeviceSelector parse(const std::string& spec);
};

// Throws Error when nothing matches (listing what is available) or when no
// OpenCL platform exists (telling the user which package to install).
DeviceInfo select_device(const DeviceSelector& selector = {});
// Sub-device `part` of `parts` equal ones (see DeviceSelector::parts), or the
// device itself when it cannot be split.
DeviceInfo split_device(const DeviceInfo& device, int parts, int part);

}  // namespace facesr::compute
