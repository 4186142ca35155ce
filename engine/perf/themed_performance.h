#pragma once
#include <string>
#include <vector>

#include "perf/performance.h"

// The FACS-based emotion performances behind builtin_performance()
// ("amazement", "anger", "fear", "pain"); see themed_performance.cpp and
// docs/performances.md for the action units, timing and sources.
namespace facesr {

Performance amazement_performance(const std::vector<std::string>& rig_names);
Performance anger_performance(const std::vector<std::string>& rig_names);
Performance fear_performance(const std::vector<std::string>& rig_names);
Performance pain_performance(const std::vector<std::string>& rig_names);

}  // namespace facesr
