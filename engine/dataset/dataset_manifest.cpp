#include "dataset/dataset_manifest.h"

#include <fstream>
#include <set>
#include <sstream>

#include "core/atomic_file.h"
#include "core/error.h"
#include "core/json_fields.h"

namespace facesr {
namespace {

using nlohmann::json;
using namespace json_fields;

// `where` is e.g. "m.json: sequences[2]".
DatasetManifest::Entry entry_from_json(const json& j, const std::string& where) {
  require(j.is_object(), where + " is not an object (got " + j.dump() + ")");
  const std::string at = where + ".";
  DatasetManifest::Entry e;
  e.name = string_field(j, "name", at);
  require(!e.name.empty(), where + ".name is empty");
  e.file = string_field(j, "file", at);
  require(!e.file.empty(), where + ".file is empty");
  e.frames = int_field(j, "frames", at, 0);
  e.split = string_field(j, "split", at);
  require(e.split == "train" || e.split == "test",
          where + ".split is '" + e.split + "', expected 'train' or 'test'");
  e.hr_mean_step_s = number_field(j, "hr_mean_step_s", at);
  e.lr_mean_step_ms = number_field(j, "lr_mean_step_ms", at);
  e.embedded_error_mean_cm = number_field(j, "embedded_error_mean_cm", at);
  e.embedded_error_max_cm = number_field(j, "embedded_error_max_cm", at);
  e.max_penetration_cm = number_field(j, "max_penetration_cm", at);
  e.complete = bool_field(j, "complete", at);
  return e;
}

}  // namespace

const DatasetManifest::Entry* DatasetManifest::find(const std::string& name) const {
  for (const Entry& e : sequences)
    if (e.name == name) return &e;
  return nullptr;
}

DatasetManifest::Entry* DatasetManifest::find(const std::string& name) {
  return const_cast<Entry*>(static_cast<const DatasetManifest*>(this)->find(name));
}

json manifest_to_json(const DatasetManifest& m) {
  json seqs = json::array();
  for (const DatasetManifest::Entry& e : m.sequences)
    seqs.push_back({{"name", e.name},
                    {"file", e.file},
                    {"frames", e.frames},
                    {"split", e.split},
                    {"hr_mean_step_s", e.hr_mean_step_s},
                    {"lr_mean_step_ms", e.lr_mean_step_ms},
                    {"embedded_error_mean_cm", e.embedded_error_mean_cm},
                    {"embedded_error_max_cm", e.embedded_error_max_cm},
                    {"max_penetration_cm", e.max_penetration_cm},
                    {"complete", e.complete}});
  return {{"format", m.format},
          {"version", m.version},
          {"units", m.units},
          {"rig_name", m.rig_name},
          {"rig_checksum", m.rig_checksum},
          {"rig_path", m.rig_path},
          {"fps", m.fps},
          {"num_lr_nodes", m.num_lr_nodes},
          {"num_surface", m.num_surface},
          {"weight_names", m.weight_names},
          {"sequences", seqs},
          {"extra", m.extra}};
}

DatasetManifest manifest_from_json(const json& j, const std::string& source) {
  require(j.is_object(), source + ": a dataset manifest must be a JSON object (got " + j.dump() + ")");
  const std::string w = source + ": ";
  DatasetManifest m;
  m.format = string_field(j, "format", w);
  require(m.format == "facesr-dataset", w + "format is '" + m.format + "', expected 'facesr-dataset'");
  m.version = int_field(j, "version", w, 0);
  require(m.version == 1, w + "unsupported manifest version " + std::to_string(m.version) +
                              " (this build reads version 1)");
  m.units = string_field(j, "units", w);
  require(m.units == "cm", w + "units are '" + m.units + "', expected 'cm'");
  m.rig_name = string_field(j, "rig_name", w);
  m.rig_checksum = u64_field(j, "rig_checksum", w);
  m.rig_path = string_field(j, "rig_path", w);
  m.fps = number_field(j, "fps", w);
  require(m.fps > 0 && m.fps <= 1000, w + "fps " + field(j, "fps", w).dump() + " is not in (0, 1000]");
  m.num_lr_nodes = int_field(j, "num_lr_nodes", w, 0);
  m.num_surface = int_field(j, "num_surface", w, 0);

  const json& names = field(j, "weight_names", w);
  require(names.is_array(), w + "weight_names is not an array");
  for (size_t i = 0; i < names.size(); ++i) {
    require(names[i].is_string(), w + "weight_names[" + std::to_string(i) + "] is not a string (got " +
                                      names[i].dump() + ")");
    m.weight_names.push_back(names[i].get<std::string>());
  }

  const json& seqs = field(j, "sequences", w);
  require(seqs.is_array(), w + "sequences is not an array");
  std::set<std::string> seen;
  for (size_t i = 0; i < seqs.size(); ++i) {
    const std::string where = w + "sequences[" + std::to_string(i) + "]";
    m.sequences.push_back(entry_from_json(seqs[i], where));
    require(seen.insert(m.sequences.back().name).second,
            where + ".name '" + m.sequences.back().name + "' appears twice");
  }
  if (j.contains("extra")) m.extra = j["extra"];
  return m;
}

void save_manifest(const std::string& path, const DatasetManifest& m) {
  const json j = manifest_to_json(m);
  manifest_from_json(j, path);  // never write a manifest this build would refuse to read
  const std::string text = j.dump(2) + "\n";
  write_file_atomically(path, [&](std::ostream& out) { out << text; });
}

DatasetManifest load_manifest(const std::string& path) {
  std::ifstream in(path);
  require(in.good(), "cannot open '" + path + "': no such file or not readable");
  std::stringstream ss;
  ss << in.rdbuf();
  json j;
  try {
    j = json::parse(ss.str());
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999
    throw Error(path + ": not valid JSON (" + e.what() + ")");
  }
  return manifest_from_json(j, path);
}

}  // namespace facesr
