#pragma once
// Typed, validated reads of JSON object fields for the engine's JSON files
// (dataset manifests, model headers). `at` is the prefix that names where a
// key lives, e.g. "m.json: " or "m.json: sequences[2].", so every message
// reads "m.json: sequences[2].split is ...".
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace facesr::json_fields {

const nlohmann::json& field(const nlohmann::json& j, const char* key, const std::string& at);
std::string string_field(const nlohmann::json& j, const char* key, const std::string& at);
// An integer in [min, INT_MAX].
int int_field(const nlohmann::json& j, const char* key, const std::string& at, int min);
uint64_t u64_field(const nlohmann::json& j, const char* key, const std::string& at);
// A finite number.
double number_field(const nlohmann::json& j, const char* key, const std::string& at);
bool bool_field(const nlohmann::json& j, const char* key, const std::string& at);
// An array of integers, each in [min, INT_MAX].
std::vector<int> int_list_field(const nlohmann::json& j, const char* key, const std::string& at, int min);

}  // namespace facesr::json_fields
