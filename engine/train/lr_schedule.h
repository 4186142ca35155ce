#pragma once
// Learning rate per epoch. The paper keeps Adam's rate constant (1e-4 for
// 2,800 epochs); on a CPU budget of tens of epochs we start higher and let
// the trainer anneal it (on ICT this lowered the validation error, not the
// test error: BENCHMARKS.md).

namespace facesr {

// Cosine annealing from lr_start (epoch 0) to lr_final (epoch epochs-1);
// constant when lr_final <= 0 or equals lr_start, or when there is one epoch.
double learning_rate_schedule(int epoch, int epochs, double lr_start, double lr_final);

}  // namespace facesr
