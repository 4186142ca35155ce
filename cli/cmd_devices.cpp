#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "compute/cl_device.h"

namespace facesr::cli {

void register_devices(CLI::App& app) {
  auto* sub = app.add_subcommand("devices", "List OpenCL platforms and devices");
  static bool json = false;
  sub->add_flag("--json", json, "Print a JSON summary on stdout");
  add_action(sub, [] {
    const auto devices = compute::list_devices();
    nlohmann::json out = nlohmann::json::array();
    for (size_t i = 0; i < devices.size(); ++i) {
      const auto& d = devices[i];
      out.push_back({{"index", i}, {"platform", d.platform_name}, {"device", d.device_name}, {"type", compute::device_type_name(d.type)},
                     {"compute_units", d.compute_units}, {"global_mem_bytes", d.global_mem_bytes}});
      if (!json) std::printf("%zu: %s / %s (%s, %u CUs)\n", i, d.platform_name.c_str(), d.device_name.c_str(),
                             compute::device_type_name(d.type), d.compute_units);
    }
    if (json) std::printf("%s\n", out.dump(2).c_str());
  });
}

}  // namespace facesr::cli
