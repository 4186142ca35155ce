// Rig and model handles: loading, information, read-only geometry.
#include <filesystem>

#include "capi_internal.h"
#include "rig/rig_io.h"

using namespace facesr;
using namespace facesr::capi;

namespace {

constexpr facesr_status kOk = FACESR_OK;

// The engine's readers size their buffer from the stream, which for a
// directory is nonsense (std::bad_alloc); name the problem instead.
void require_not_directory(const char* path, const char* what) {
  std::error_code ec;
  require(!std::filesystem::is_directory(path, ec),
          "'" + std::string(path) + "' is a directory, not a " + what + " file");
}

}  // namespace

extern "C" {

facesr_status facesr_rig_load(const char* path, facesr_rig** out_rig) {
  static const char* fn = "facesr_rig_load";
  if (!out_rig) return null_argument(fn, "out_rig");
  *out_rig = nullptr;
  if (!path) return null_argument(fn, "path");
  return guarded(fn, FACESR_ERROR_FILE, [&] {
    require_not_directory(path, "rig");
    auto loaded = std::make_shared<LoadedRig>();
    auto rig = std::make_shared<const Rig>(load_rig(path));
    loaded->checksum = rig_checksum(*rig);
    for (int32_t i = 0; i < rig->num_blendshapes(); ++i) loaded->index.emplace(rig->blendshape_names[size_t(i)], i);
    loaded->rig = std::move(rig);
    auto handle = std::make_unique<facesr_rig>();
    handle->loaded = std::move(loaded);
    *out_rig = handle.release();
    return kOk;
  });
}

void facesr_rig_free(facesr_rig* rig) { delete rig; }

facesr_status facesr_rig_get_info(const facesr_rig* rig, facesr_rig_info* info) {
  static const char* fn = "facesr_rig_get_info";
  if (!rig) return null_argument(fn, "rig");
  if (!info) return null_argument(fn, "info");
  if (const facesr_status s = check_info_size(fn, "facesr_rig_info", info->struct_size)) return s;
  const Rig& r = *rig->loaded->rig;
  FACESR_PUT(info, num_blendshapes, r.num_blendshapes());
  FACESR_PUT(info, num_surface_vertices, r.num_surface_vertices());
  FACESR_PUT(info, num_surface_triangles, r.surface_tris.rows());
  FACESR_PUT(info, num_lr_nodes, r.lr.mesh.X.rows());
  FACESR_PUT(info, num_muscles, r.muscles.size());
  FACESR_PUT(info, checksum, rig->loaded->checksum);
  for (int c = 0; c < 3; ++c) {
    put_field(info, offsetof(facesr_rig_info, jaw_pivot) + c * sizeof(float), float(r.jaw.pivot[c]));
    put_field(info, offsetof(facesr_rig_info, jaw_axis) + c * sizeof(float), float(r.jaw.axis[c]));
  }
  return kOk;
}

facesr_status facesr_rig_blendshape_name(const facesr_rig* rig, int32_t index, char* buf, int32_t buf_size,
                                         int32_t* out_length) {
  static const char* fn = "facesr_rig_blendshape_name";
  if (!rig) return null_argument(fn, "rig");
  if (!buf && buf_size != 0) return null_argument(fn, "buf (with buf_size > 0)");
  return guarded(fn, FACESR_ERROR_INVALID_ARGUMENT, [&] {
    const auto& names = rig->loaded->rig->blendshape_names;
    require(buf_size >= 0, "buf_size is " + std::to_string(buf_size) + ", must be >= 0");
    require(index >= 0 && size_t(index) < names.size(),
            "blendshape index " + std::to_string(index) + " is out of range [0, " + std::to_string(names.size()) + ")");
    const std::string& name = names[size_t(index)];
    if (buf_size > 0) {
      const size_t n = std::min(name.size(), size_t(buf_size) - 1);
      std::memcpy(buf, name.data(), n);
      buf[n] = '\0';
    }
    if (out_length) *out_length = int32_t(name.size());
    return kOk;
  });
}

facesr_status facesr_rig_blendshape_index(const facesr_rig* rig, const char* name, int32_t* out_index) {
  static const char* fn = "facesr_rig_blendshape_index";
  if (!rig) return null_argument(fn, "rig");
  if (!name) return null_argument(fn, "name");
  if (!out_index) return null_argument(fn, "out_index");
  return guarded(fn, FACESR_ERROR_INTERNAL, [&] {
    const LoadedRig& l = *rig->loaded;
    const auto it = l.index.find(name);
    if (it == l.index.end())
      return fail(FACESR_ERROR_NOT_FOUND, fn,
                  "no blendshape named '" + std::string(name) + "' in rig '" + l.rig->name +
                      "' (names are case-sensitive ARKit names)");
    *out_index = it->second;
    return kOk;
  });
}

facesr_status facesr_rig_get_triangles(const facesr_rig* rig, int32_t* indices, int64_t count) {
  static const char* fn = "facesr_rig_get_triangles";
  if (!rig) return null_argument(fn, "rig");
  if (!indices) return null_argument(fn, "indices");
  const Tris& F = rig->loaded->rig->surface_tris;
  if (count != F.size()) return wrong_count(fn, "indices", count, F.size(), "3 * num_surface_triangles");
  std::memcpy(indices, F.data(), size_t(F.size()) * sizeof(int32_t));
  return kOk;
}

facesr_status facesr_rig_get_rest_positions(const facesr_rig* rig, float* xyz, int64_t count) {
  static const char* fn = "facesr_rig_get_rest_positions";
  if (!rig) return null_argument(fn, "rig");
  if (!xyz) return null_argument(fn, "xyz");
  const Points& V = rig->loaded->rig->surface;
  if (count != V.size()) return wrong_count(fn, "xyz", count, V.size(), "3 * num_surface_vertices");
  for (int64_t i = 0; i < count; ++i) xyz[i] = float(V.data()[i]);
  return kOk;
}

facesr_status facesr_model_load(const char* path, facesr_model** out_model) {
  static const char* fn = "facesr_model_load";
  if (!out_model) return null_argument(fn, "out_model");
  *out_model = nullptr;
  if (!path) return null_argument(fn, "path");
  return guarded(fn, FACESR_ERROR_FILE, [&] {
    require_not_directory(path, "model");
    auto model = std::make_shared<const SrModel>(load_sr_model(path));
    // The runtime runs only the network; a baseline model would load here and
    // fail later at context creation, so say so now, naming the file.
    require(model->arch.kind == "sr", std::string(path) + ": a '" + model->arch.kind +
                                          "' baseline model; the runtime needs the super-resolution network ('sr')");
    auto handle = std::make_unique<facesr_model>();
    for (const SrTensor& t : model->tensors) handle->num_parameters += int64_t(t.values.size());
    handle->model = std::move(model);
    *out_model = handle.release();
    return kOk;
  });
}

void facesr_model_free(facesr_model* model) { delete model; }

facesr_status facesr_model_get_info(const facesr_model* model, facesr_model_info* info) {
  static const char* fn = "facesr_model_get_info";
  if (!model) return null_argument(fn, "model");
  if (!info) return null_argument(fn, "info");
  if (const facesr_status s = check_info_size(fn, "facesr_model_info", info->struct_size)) return s;
  const SrModel& m = *model->model;
  FACESR_PUT(info, rig_checksum, m.rig_checksum);
  FACESR_PUT(info, num_lr_nodes, m.num_lr);
  FACESR_PUT(info, num_surface_vertices, m.num_hr);
  FACESR_PUT(info, num_parameters, std::min<int64_t>(model->num_parameters, INT32_MAX));
  return kOk;
}

}  // extern "C"
