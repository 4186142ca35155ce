#pragma once
#include <string>
#include <vector>

namespace facesr::cli {

// "a,b,,c" → {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& s);
// "64,128" → {64, 128}; Error naming `option` on anything but positive integers.
std::vector<int> int_list(const std::string& s, const std::string& option);
// "0.5,-2" → {0.5, −2}; Error naming `option` on anything but finite numbers.
std::vector<double> double_list(const std::string& s, const std::string& option);

}  // namespace facesr::cli
