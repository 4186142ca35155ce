#pragma once
// The recipe of `facesr character build`: how a wall-clock budget is shared
// between the stages, and which built-in performances make the training
// data. The choices follow what the ICT model's history in BENCHMARKS.md
// measured: test error fell with the variety of training takes, not with
// epochs alone (stages 2–5); near-rest data and zero_rest decide the frames
// that return to rest (stages 6–8).
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace facesr {

struct CharacterBudget {
  double total_s = 0;
  double dataset_s = 0;  // LR + HR simulation of the test split and the training takes
  double train_a_s = 0;  // training at the base rate
  double train_b_s = 0;  // annealed fine-tune with zero_rest
  double finish_s = 0;   // post-fit choices, evaluation, package (estimate, not a cap)
  nlohmann::json to_json() const;
};

// "3h", "90m", "45s", "1.5h" or a plain number of seconds; Error otherwise
// (and for a duration that is not positive and finite).
double parse_duration_s(const std::string& text);

// 45 % simulation, 27 % + 18 % training, 10 % the rest.
CharacterBudget split_budget(double total_s);

// The test split: the paper's unseen expressions.
std::vector<std::string> character_test_performances();

// Training takes in the order they are added: the paper's two, near-rest
// "nudge" (single shapes at small weights: what the near-rest correctives
// are fitted on), then the varied generators and the "sparse-K" takes
// (up to `sparse_takes` of them, K = 2, 3, ...).
std::vector<std::string> character_training_order(int sparse_takes = 40);

// The training takes whose HR frames fit `seconds` at `hr_s_per_frame`:
// a prefix of character_training_order(), never fewer than the first two.
// frames_of gives a take's frame count (already capped by any frame limit).
std::vector<std::string> plan_training_performances(double seconds, double hr_s_per_frame,
                                                    const std::function<int(const std::string&)>& frames_of);

}  // namespace facesr
