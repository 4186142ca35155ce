#pragma once
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

// The manifest of a paired LR/HR dataset: one JSON file beside the .fsd
// sequences that says which rig they come from, what they hold, how each one
// is used (train or test) and a few summary numbers, so a dataset can be
// listed and split without opening every sequence. JSON keys are the field
// names below; every field is required except "extra" (free-form, for
// whoever builds the dataset to record how, e.g. solver settings).
namespace facesr {

struct DatasetManifest {
  std::string format = "facesr-dataset";
  int version = 1;
  std::string units = "cm";
  std::string rig_name;
  uint64_t rig_checksum = 0;
  std::string rig_path;
  double fps = 30;
  int num_lr_nodes = 0, num_surface = 0;
  std::vector<std::string> weight_names;

  // One performance. Numbers are -1 when not measured (e.g. not complete).
  struct Entry {
    std::string name;  // performance name, unique in the manifest
    std::string file;  // the .fsd, relative to the manifest's folder
    int frames = 0;
    std::string split = "train";  // "train" | "test"
    double hr_mean_step_s = -1, lr_mean_step_ms = -1;
    double embedded_error_mean_cm = -1, embedded_error_max_cm = -1;
    double max_penetration_cm = -1;
    bool complete = false;  // the .fsd is committed
  };
  std::vector<Entry> sequences;
  nlohmann::json extra = nlohmann::json::object();

  // The entry with this name, or null.
  const Entry* find(const std::string& name) const;
  Entry* find(const std::string& name);
};

// Validates (like load_manifest) and writes the manifest atomically.
void save_manifest(const std::string& path, const DatasetManifest& m);

// Reads and validates a manifest: format "facesr-dataset", version 1, units
// "cm", every field present with the right type, counts >= 0, finite numbers,
// split "train" or "test", unique sequence names. Every Error names `path`
// and the offending key (e.g. "sequences[2].split").
DatasetManifest load_manifest(const std::string& path);

nlohmann::json manifest_to_json(const DatasetManifest& m);

// Whether frame f of a training sequence is held out for validation when
// every `validation_every`-th frame is (0: none): the one rule that training,
// `facesr eval --split validation` and fits on training frames share.
inline bool is_validation_frame(int f, int validation_every) {
  return validation_every > 0 && f % validation_every == validation_every - 1;
}
// `source` names the origin in errors (a path, or "manifest").
DatasetManifest manifest_from_json(const nlohmann::json& j, const std::string& source);

}  // namespace facesr
