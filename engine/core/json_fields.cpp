#include "core/json_fields.h"

#include <climits>
#include <cmath>

#include "core/error.h"

namespace facesr::json_fields {

using nlohmann::json;

const json& field(const json& j, const char* key, const std::string& at) {
  require(j.contains(key), at + key + " is missing");
  return j[key];
}

std::string string_field(const json& j, const char* key, const std::string& at) {
  const json& v = field(j, key, at);
  require(v.is_string(), at + key + " is not a string (got " + v.dump() + ")");
  return v.get<std::string>();
}

namespace {
bool int_fits(const json& v, int min) {
  return v.is_number_unsigned() ? v.get<uint64_t>() <= uint64_t(INT_MAX)
                                : v.get<int64_t>() >= min && v.get<int64_t>() <= INT_MAX;
}
std::string range(int min) { return "[" + std::to_string(min) + ", " + std::to_string(INT_MAX) + "]"; }
}  // namespace

int int_field(const json& j, const char* key, const std::string& at, int min) {
  const json& v = field(j, key, at);
  require(v.is_number_integer(), at + key + " is not an integer (got " + v.dump() + ")");
  require(int_fits(v, min), at + key + " is " + v.dump() + ", expected an integer in " + range(min));
  return v.get<int>();
}

uint64_t u64_field(const json& j, const char* key, const std::string& at) {
  const json& v = field(j, key, at);
  require(v.is_number_unsigned(), at + key + " is not an unsigned integer (got " + v.dump() + ")");
  return v.get<uint64_t>();
}

double number_field(const json& j, const char* key, const std::string& at) {
  const json& v = field(j, key, at);
  require(v.is_number(), at + key + " is not a number (got " + v.dump() + ")");
  const double d = v.get<double>();
  require(std::isfinite(d), at + key + " is not finite");
  return d;
}

bool bool_field(const json& j, const char* key, const std::string& at) {
  const json& v = field(j, key, at);
  require(v.is_boolean(), at + key + " is not true or false (got " + v.dump() + ")");
  return v.get<bool>();
}

std::vector<int> int_list_field(const json& j, const char* key, const std::string& at, int min) {
  const json& v = field(j, key, at);
  require(v.is_array(), at + key + " is not an array (got " + v.dump() + ")");
  std::vector<int> out;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string where = at + key + "[" + std::to_string(i) + "]";
    require(v[i].is_number_integer(), where + " is not an integer (got " + v[i].dump() + ")");
    require(int_fits(v[i], min), where + " is " + v[i].dump() + ", expected an integer in " + range(min));
    out.push_back(v[i].get<int>());
  }
  return out;
}

}  // namespace facesr::json_fields
