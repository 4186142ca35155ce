#include "train/train_device.h"

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
  const unsigned n = std::thread::hardware_concurrency();
  if (n > 0) torch::set_num_threads(int(n));
}

}  // namespace facesr
