#include "train/lr_schedule.h"

#include <algorithm>
#include <cmath>

namespace facesr {

double learning_rate_schedule(int epoch, int epochs, double lr_start, double lr_final) {
  if (epochs <= 1 || lr_final <= 0 || lr_final == lr_start) return lr_start;
  const double s = double(std::clamp(epoch, 0, epochs - 1)) / double(epochs - 1);
  return lr_final + 0.5 * (lr_start - lr_final) * (1 + std::cos(M_PI * s));
}

}  // namespace facesr
