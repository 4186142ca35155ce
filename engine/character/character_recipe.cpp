#include "character/character_recipe.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/error.h"

namespace facesr {

nlohmann::json CharacterBudget::to_json() const {
  return {{"total_s", total_s},     {"dataset_s", dataset_s}, {"train_a_s", train_a_s},
          {"train_b_s", train_b_s}, {"finish_s", finish_s}};
}

CharacterBudget split_budget(double total_s) {
  require(total_s > 0, "character build: the budget must be positive (got " + std::to_string(total_s) + " s)");
  CharacterBudget b;
  b.total_s = total_s;
  b.dataset_s = 0.45 * total_s;
  b.train_a_s = 0.27 * total_s;
  b.train_b_s = 0.18 * total_s;
  b.finish_s = total_s - b.dataset_s - b.train_a_s - b.train_b_s;
  return b;
}

double parse_duration_s(const std::string& text) {
  const std::string bad = "duration '" + text + "' is not a positive number with an optional unit h, m or s (e.g. 3h, 90m)";
  require(!text.empty(), bad);
  double scale = 1;
  std::string num = text;
  switch (text.back()) {
    case 'h': scale = 3600, num.pop_back(); break;
    case 'm': scale = 60, num.pop_back(); break;
    case 's': num.pop_back(); break;
    default: break;
  }
  size_t used = 0;
  double v = 0;
  try {
    v = std::stod(num, &used);
  } catch (const std::exception&) {
    throw Error(bad);
  }
  require(used == num.size() && std::isfinite(v) && v > 0, bad);
  return v * scale;
}

std::vector<std::string> character_test_performances() { return {"anger", "fear"}; }

std::vector<std::string> character_training_order(int sparse_takes) {
  std::vector<std::string> out = {"amazement", "pain", "nudge", "random", "sparse", "talk", "subtle"};
  for (int k = 2; k <= sparse_takes + 1 && k <= 99; ++k) out.push_back("sparse-" + std::to_string(k));
  return out;
}

std::vector<std::string> plan_training_performances(double seconds, double hr_s_per_frame,
                                                    const std::function<int(const std::string&)>& frames_of) {
  require(hr_s_per_frame > 0, "character build: the HR time per frame must be positive");
  std::vector<std::string> out;
  double planned = 0;
  for (const std::string& name : character_training_order()) {
    const double cost = frames_of(name) * hr_s_per_frame;
    if (out.size() >= 2 && planned + cost > seconds) break;
    out.push_back(name);
    planned += cost;
  }
  return out;
}

}  // namespace facesr
