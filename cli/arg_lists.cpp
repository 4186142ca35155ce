#include "arg_lists.h"

#include <cmath>
#include <cstdlib>

#include "core/error.h"

namespace facesr::cli {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::string cur;
  for (char ch : s + ",") {
    if (ch == ',') {
      if (!cur.empty()) out.push_back(cur);
      cur.clear();
    } else {
      cur.push_back(ch);
    }
  }
  return out;
}

std::vector<int> int_list(const std::string& s, const std::string& option) {
  std::vector<int> out;
  for (const std::string& item : split_list(s)) {
    char* end = nullptr;
    const long v = std::strtol(item.c_str(), &end, 10);
    require(end && *end == '\0' && v >= 1 && v <= 1 << 20,
            option + ": '" + item + "' is not a positive integer (expected a list like 64,128)");
    out.push_back(int(v));
  }
  return out;
}

std::vector<double> double_list(const std::string& s, const std::string& option) {
  std::vector<double> out;
  for (const std::string& item : split_list(s)) {
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    require(end && *end == '\0' && std::isfinite(v), option + ": '" + item + "' is not a finite number");
    out.push_back(v);
  }
  return out;
}

}  // namespace facesr::cli
