#include "train/train_device.h"

#include <sched.h>

#include <thread>

#include "core/error.h"

namespace facesr {

torch::Device training_device(const std::string& choice) {
  if (choice == "cpu") return torch::kCPU;
  if (choice == "cuda") {
    require(torch::cuda::is_available(),
            "training device 'cuda': this LibTorch build has no CUDA or no GPU is visible (use --device cpu)");
    return torch::kCUDA;
  }
  require(choice == "auto", "training device '" + choice + "': expected cpu, cuda or auto");
  return torch::cuda::is_available() ? torch::Device(torch::kCUDA) : torch::Device(torch::kCPU);
}

void use_all_cores() {
  // The cores this process may run on (taskset, cgroups), not the machine's:
  // more threads than that only contend.
  cpu_set_t set;
  CPU_ZERO(&set);
  int n = sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
  if (n <= 0) n = int(std::thread::hardware_concurrency());
  if (n > 0) torch::set_num_threads(n);
}

}  // namespace facesr
