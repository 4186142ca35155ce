#include <algorithm>
#include <cstring>
#include <cmath>
#include <fstream>

#include "core/atomic_file.h"
#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "core/framed_file.h"
#include "core/json_fields.h"
#include "sr/sr_model.h"

namespace facesr {

using nlohmann::json;

namespace {

const char kMagic[8] = {'F', 'A', 'C', 'E', 'S', 'R', 'S', 'M'};
// Version 2 added the surface embedding (embed_nodes, embed_weights),
// version 4 the near-rest correctives, version 5 the residual smoothing (a
// header entry only: a version-4 reader would ignore it and give another
// surface). Version 3 (one sample per shape, "rest_tangents"; one
// development commit) is not read. Version 6 added geometry.pe_rows (a model
// carried over to another rig, `facesr model transfer`). A model without
// pe_rows is still written as version 5, byte for byte as before.
constexpr uint32_t kVersion = 6;

uint32_t version_of(const SrModel& m) { return m.geometry.pe_rows.empty() ? 5 : kVersion; }

template <class T>
void check_size(const std::vector<T>& v, size_t n, const std::string& ctx, const char* what) {
  require(v.size() == n, ctx + ": " + what + " has " + std::to_string(v.size()) + " values, expected " +
                             std::to_string(n));
}

void check_finite(const std::vector<float>& v, const std::string& ctx, const std::string& what) {
  for (size_t i = 0; i < v.size(); ++i)
    require(std::isfinite(v[i]), ctx + ": " + what + "[" + std::to_string(i) + "] is not finite");
}

void check_indices(const std::vector<int32_t>& v, int lo, int hi, const std::string& ctx, const char* what) {
  for (size_t i = 0; i < v.size(); ++i)
    require(v[i] >= lo && v[i] < hi, ctx + ": " + what + "[" + std::to_string(i) + "] = " + std::to_string(v[i]) +
                                         " is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + ")");
}

json header_json(const SrModel& m) {
  return {{"format", "facesr-sr-model"}, {"version", version_of(m)},       {"units", "cm"},
          {"rig_name", m.rig_name},      {"rig_checksum", m.rig_checksum}, {"num_lr", m.num_lr},
          {"num_hr", m.num_hr},          {"architecture", architecture_to_json(m.arch)}, {"training", m.training}};
}

json header_with_correctives(const SrModel& m) {
  json h = header_json(m);
  if (!m.rest_correctives.empty()) h["rest_correctives"] = rest_correctives_to_json(m.rest_correctives);
  if (!m.residual_smoothing.empty()) h["residual_smoothing"] = residual_smoothing_to_json(m.residual_smoothing);
  return h;
}

}  // namespace

const SrTensor& SrModel::tensor(const std::string& name) const {
  for (const SrTensor& t : tensors)
    if (t.name == name) return t;
  throw Error("model has no parameter tensor '" + name + "'");
}

void validate_sr_model(const SrModel& m, const std::string& ctx) {
  require(m.num_lr > 0 && m.num_hr > 0, ctx + ": num_lr and num_hr must be positive");
  const size_t N = size_t(m.num_lr), M = size_t(m.num_hr);
  const SrGeometry& g = m.geometry;
  require(g.num_lr == m.num_lr && g.num_hr == m.num_hr,
          ctx + ": the geometry is for " + std::to_string(g.num_lr) + " LR nodes and " + std::to_string(g.num_hr) +
              " HR vertices, the model for " + std::to_string(N) + " and " + std::to_string(M));
  check_size(g.lr_rest, 3 * N, ctx, "geometry.lr_rest");
  check_size(g.hr_rest, 3 * M, ctx, "geometry.hr_rest");
  check_finite(g.lr_rest, ctx, "geometry.lr_rest");
  check_finite(g.hr_rest, ctx, "geometry.hr_rest");
  if (!g.hr_rest_lr_frame.empty()) {
    check_size(g.hr_rest_lr_frame, 3 * M, ctx, "geometry.hr_rest_lr_frame");
    check_finite(g.hr_rest_lr_frame, ctx, "geometry.hr_rest_lr_frame");
  }
  if (m.arch.embedded_skip || !g.embed_nodes.empty()) {
    check_size(g.embed_nodes, 4 * M, ctx, "geometry.embed_nodes");
    check_size(g.embed_weights, 4 * M, ctx, "geometry.embed_weights");
    check_indices(g.embed_nodes, 0, int(N), ctx, "geometry.embed_nodes");
    check_finite(g.embed_weights, ctx, "geometry.embed_weights");
  }
  require(g.hr_tris.size() % 3 == 0, ctx + ": geometry.hr_tris is not a list of triangles");
  check_indices(g.hr_tris, 0, int(M), ctx, "geometry.hr_tris");
  if (m.arch.kind == "sr") {
    require(g.graph_k == m.arch.graph_k && g.upsample_k == m.arch.upsample_k,
            ctx + ": the geometry's k (graph " + std::to_string(g.graph_k) + ", upsampling " +
                std::to_string(g.upsample_k) + ") differs from the architecture's (" + std::to_string(m.arch.graph_k) +
                ", " + std::to_string(m.arch.upsample_k) + ")");
    const size_t K = size_t(g.upsample_k);
    check_size(g.lr_graph, N * size_t(g.graph_k), ctx, "geometry.lr_graph");
    check_size(g.lr_to_hr, N, ctx, "geometry.lr_to_hr");
    check_size(g.up_index, M * K, ctx, "geometry.up_index");
    check_size(g.up_dist, M * K, ctx, "geometry.up_dist");
    check_size(g.euclid_index, M * K, ctx, "geometry.euclid_index");
    check_size(g.euclid_dist, M * K, ctx, "geometry.euclid_dist");
    check_indices(g.lr_graph, 0, int(N), ctx, "geometry.lr_graph");
    check_indices(g.lr_to_hr, -1, int(M), ctx, "geometry.lr_to_hr");
    check_indices(g.up_index, 0, int(N), ctx, "geometry.up_index");
    check_indices(g.euclid_index, 0, int(N), ctx, "geometry.euclid_index");
    check_finite(g.up_dist, ctx, "geometry.up_dist");
    check_finite(g.euclid_dist, ctx, "geometry.euclid_dist");
    if (!g.up_is_euclid.empty()) check_size(g.up_is_euclid, M * K, ctx, "geometry.up_is_euclid");
    if (!g.pe_rows.empty()) {
      check_size(g.pe_rows, N, ctx, "geometry.pe_rows");
      // Rows are node indices of the rig the weights were trained on; the bound only keeps sin/cos arguments sane.
      check_indices(g.pe_rows, 0, 1 << 24, ctx, "geometry.pe_rows");
    }
  } else {
    require(g.pe_rows.empty(), ctx + ": geometry.pe_rows applies to the super-resolution network only");
  }
  const auto expected = parameter_shapes(m.arch, m.num_lr, m.num_hr);
  require(m.tensors.size() == expected.size(), ctx + ": " + std::to_string(m.tensors.size()) +
                                                   " parameter tensors, the architecture has " +
                                                   std::to_string(expected.size()));
  for (size_t i = 0; i < expected.size(); ++i) {
    const SrTensor& t = m.tensors[i];
    require(t.name == expected[i].first,
            ctx + ": parameter " + std::to_string(i) + " is '" + t.name + "', expected '" + expected[i].first + "'");
    require(t.shape == expected[i].second, ctx + ": parameter '" + t.name + "' has the wrong shape for this architecture");
    size_t n = 1;
    for (int64_t d : t.shape) n *= size_t(d);
    check_size(t.values, n, ctx, ("parameter '" + t.name + "'").c_str());
    check_finite(t.values, ctx, "parameter '" + t.name + "'");
  }
  if (!m.rest_correctives.empty()) {
    require(m.arch.kind == "sr", ctx + ": rest correctives apply to the super-resolution network only");
    validate_rest_correctives(m.rest_correctives, m.num_lr, m.num_hr, ctx);
  }
  validate_residual_smoothing(m.residual_smoothing, ctx);
  if (!m.residual_smoothing.empty()) {
    require(m.arch.kind == "sr" && m.arch.embedded_skip,
            ctx + ": residual smoothing needs the super-resolution network with the embedded skip");
    require(!g.hr_tris.empty(), ctx + ": residual smoothing needs the surface triangles (geometry.hr_tris)");
  }
}

void save_sr_model(const std::string& path, const SrModel& m) {
  validate_sr_model(m, path);
  ByteWriter w;
  for (char c : kMagic) w.put(c);
  w.put(version_of(m));
  w.put_string(header_with_correctives(m).dump());
  const SrGeometry& g = m.geometry;
  w.put_vector(g.lr_rest);
  w.put_vector(g.hr_rest);
  w.put_vector(g.hr_rest_lr_frame);
  w.put_vector(g.hr_tris);
  w.put_vector(g.lr_graph);
  w.put_vector(g.lr_to_hr);
  w.put_vector(g.up_index);
  w.put_vector(g.up_dist);
  w.put_vector(g.euclid_index);
  w.put_vector(g.euclid_dist);
  w.put_vector(g.up_is_euclid);
  w.put_vector(g.embed_nodes);
  w.put_vector(g.embed_weights);
  if (version_of(m) >= 6) w.put_vector(g.pe_rows);
  w.put<uint64_t>(m.tensors.size());
  for (const SrTensor& t : m.tensors) {
    w.put_string(t.name);
    w.put_vector(t.shape);
    w.put_vector(t.values);
  }
  w.put_vector(m.rest_correctives.lr);
  w.put_vector(m.rest_correctives.hr);
  w.put(fnv1a64(w.bytes().data(), w.bytes().size()));
  write_file_atomically(path, [&](std::ostream& o) {
    o.write(reinterpret_cast<const char*>(w.bytes().data()), std::streamsize(w.bytes().size()));
  });
}

SrModel load_sr_model(const std::string& path) {
  std::ifstream probe(path, std::ios::binary);
  require(probe.good(), "cannot open model '" + path + "': no such file or not readable");
  probe.close();
  const std::vector<uint8_t> bytes = read_file_bytes(path);
  require(bytes.size() >= 20 && std::equal(kMagic, kMagic + 8, bytes.begin()),
          path + ": not a facesr model file (no FACESRSM magic)");
  uint64_t stored;
  std::memcpy(&stored, bytes.data() + bytes.size() - 8, 8);
  require(stored == fnv1a64(bytes.data(), bytes.size() - 8),
          path + ": checksum mismatch: the file is corrupt or truncated");
  ByteReader r(bytes.data() + 8, bytes.size() - 16, path);
  const auto version = r.get<uint32_t>("format version");
  require(version == 2 || version == 4 || version == 5 || version == kVersion,
          path + ": model format version " + std::to_string(version) +
              " is not supported (this build reads versions 2, 4, 5 and " + std::to_string(kVersion) +
              "; remake a version-3 model with `facesr model correctives`)");
  json h;
  try {
    h = json::parse(r.get_string("header"));
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e999 (found by fuzzing)
    throw Error(path + ": the header is not valid JSON (" + e.what() + ")");
  }
  using namespace json_fields;
  const std::string at = path + ": ";
  require(h.is_object(), at + "the header is not a JSON object");
  require(string_field(h, "format", at) == "facesr-sr-model", at + "format is not 'facesr-sr-model'");
  require(string_field(h, "units", at) == "cm", at + "units are not 'cm'");
  SrModel m;
  m.rig_name = string_field(h, "rig_name", at);
  m.rig_checksum = u64_field(h, "rig_checksum", at);
  m.num_lr = int_field(h, "num_lr", at, 1);
  m.num_hr = int_field(h, "num_hr", at, 1);
  m.arch = architecture_from_json(field(h, "architecture", at), path);
  if (h.contains("training")) m.training = h["training"];
  SrGeometry& g = m.geometry;
  g.num_lr = m.num_lr;
  g.num_hr = m.num_hr;
  g.graph_k = m.arch.graph_k;
  g.upsample_k = m.arch.upsample_k;
  g.lr_rest = r.get_vector<float>("geometry.lr_rest");
  g.hr_rest = r.get_vector<float>("geometry.hr_rest");
  g.hr_rest_lr_frame = r.get_vector<float>("geometry.hr_rest_lr_frame");
  g.hr_tris = r.get_vector<int32_t>("geometry.hr_tris");
  g.lr_graph = r.get_vector<int32_t>("geometry.lr_graph");
  g.lr_to_hr = r.get_vector<int32_t>("geometry.lr_to_hr");
  g.up_index = r.get_vector<int32_t>("geometry.up_index");
  g.up_dist = r.get_vector<float>("geometry.up_dist");
  g.euclid_index = r.get_vector<int32_t>("geometry.euclid_index");
  g.euclid_dist = r.get_vector<float>("geometry.euclid_dist");
  g.up_is_euclid = r.get_vector<uint8_t>("geometry.up_is_euclid");
  g.embed_nodes = r.get_vector<int32_t>("geometry.embed_nodes");
  g.embed_weights = r.get_vector<float>("geometry.embed_weights");
  if (version >= 6) g.pe_rows = r.get_vector<int32_t>("geometry.pe_rows");
  const auto count = r.get<uint64_t>("tensor count");
  require(count <= 4096, at + "implausible tensor count " + std::to_string(count));
  for (uint64_t i = 0; i < count; ++i) {
    SrTensor t;
    t.name = r.get_string("tensor name");
    t.shape = r.get_vector<int64_t>("tensor shape", 8);
    t.values = r.get_vector<float>("tensor values");
    m.tensors.push_back(std::move(t));
  }
  if (version >= 4) {
    RestCorrectives& rt = m.rest_correctives;
    if (h.contains("rest_correctives")) rest_correctives_from_json(h["rest_correctives"], rt, path);
    rt.lr = r.get_vector<float>("rest corrective LR directions");
    rt.hr = r.get_vector<float>("rest corrective HR residuals");
    require(!rt.empty() || (rt.lr.empty() && rt.hr.empty()),
            at + "rest corrective arrays without a \"rest_correctives\" header entry");
  }
  if (version >= 5 && h.contains("residual_smoothing"))
    m.residual_smoothing = residual_smoothing_from_json(h["residual_smoothing"], path);
  require(r.remaining() == 0, at + std::to_string(r.remaining()) + " unexpected bytes before the checksum");
  validate_sr_model(m, path);
  return m;
}

void require_model_matches_rig(const SrModel& m, uint64_t rig_checksum, int num_lr, int num_hr,
                               const std::string& model_name, const std::string& rig_name) {
  require(m.rig_checksum == rig_checksum,
          model_name + " was trained on rig '" + m.rig_name + "' (checksum " + hex64(m.rig_checksum) +
              "), not on " + rig_name + " (checksum " + hex64(rig_checksum) + ")");
  require(m.num_lr == num_lr && m.num_hr == num_hr,
          model_name + " expects " + std::to_string(m.num_lr) + " LR nodes and " + std::to_string(m.num_hr) +
              " HR vertices; " + rig_name + " has " + std::to_string(num_lr) + " and " + std::to_string(num_hr));
}

}  // namespace facesr
