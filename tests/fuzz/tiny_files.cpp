#include "tiny_files.h"

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "dataset/dataset_manifest.h"
#include "mesh/obj_io.h"
#include "perf/performance.h"
#include "perf/sequence_io.h"
#include "rig/rig_io.h"
#include "sr/coordinate_frame.h"
#include "sr/sr_model.h"

namespace fs = std::filesystem;

namespace facesr::tiny {

namespace {

// Deterministic, finite, of both signs and several magnitudes.
float value(size_t i) { return 0.1f * std::sin(0.7f * float(i) + 0.3f); }

SrModel model(const Rig& r, bool pe_rows) {
  SrModel m;
  m.arch.pe_dim = 4;
  m.arch.encoder_dims = {4};
  m.arch.graph_k = 2;
  m.arch.upsample_k = 3;
  m.arch.weight_hidden = {4};
  m.arch.recon_hidden = {4};
  m.arch.input_scale = 0.2;
  m.arch.output_scale = 0.3;
  m.rig_name = r.name;
  m.rig_checksum = rig_checksum(r);
  SrGeometryOptions go;
  go.graph_k = m.arch.graph_k;
  go.upsample_k = m.arch.upsample_k;
  m.geometry = build_sr_geometry(r, go);
  m.num_lr = m.geometry.num_lr;
  m.num_hr = m.geometry.num_hr;
  if (pe_rows) {
    // Also the optional parts: smoothing and the positional-encoding rows of a transferred model.
    for (int i = 0; i < m.num_lr; ++i) m.geometry.pe_rows.push_back(m.num_lr - 1 - i);
    m.arch.embedded_skip = true;  // residual smoothing smooths the correction to the embedding
    m.residual_smoothing.iterations = 2;
    m.residual_smoothing.lambda = 0.5;
    m.training = {{"note", "tiny fuzz seed"}};
    m.rest_correctives.shapes = {"jawOpen"};
    m.rest_correctives.amplitudes = {{0.5f, 1.0f}};
    for (int i = 0; i < 3 * m.num_lr; ++i) m.rest_correctives.lr.push_back(value(size_t(500 + i)));
    for (int i = 0; i < 2 * 3 * m.num_hr; ++i) m.rest_correctives.hr.push_back(value(size_t(700 + i)));
  }
  set_coordinate_frame(m.arch, m.geometry);
  size_t k = 0;
  for (const auto& [name, shape] : parameter_shapes(m.arch, m.num_lr, m.num_hr)) {
    SrTensor t{name, shape, {}};
    size_t n = 1;
    for (auto d : shape) n *= size_t(d);
    for (size_t i = 0; i < n; ++i) t.values.push_back(value(k++));
    m.tensors.push_back(std::move(t));
  }
  return m;
}

void write_text(const fs::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary | std::ios::trunc);
  out << text;
  require(out.good(), "cannot write " + p.string());
}

}  // namespace

std::vector<std::string> write_seed_files(const std::string& dir, const std::string& livelink_dir) {
  std::vector<std::string> written;
  auto folder = [&](const std::string& target) {
    const fs::path p = fs::path(dir) / target;
    fs::create_directories(p);
    return p;
  };
  auto note = [&](const fs::path& p) { written.push_back(p.string()); };
  const Rig r = rig();
  const int N = int(r.lr.mesh.X.rows()), S = int(r.surface.rows());

  {  // .rig
    const fs::path d = folder("rig");
    save_rig(r, (d / "tiny.rig").string());
    note(d / "tiny.rig");
  }
  {  // .fsm: the network alone, and with every optional part
    const fs::path d = folder("model");
    save_sr_model((d / "plain.fsm").string(), model(r, false));
    save_sr_model((d / "pe_rows.fsm").string(), model(r, true));
    note(d / "plain.fsm");
    note(d / "pe_rows.fsm");
  }
  {  // .fsq, LR and HR
    const fs::path d = folder("sequence");
    for (const char* res : {"low", "high"}) {
      Sequence q;
      q.header.resolution = res;
      q.header.rig_checksum = rig_checksum(r);
      q.header.num_nodes = uint64_t(N);
      q.header.num_surface = uint64_t(S);
      for (int f = 0; f < 3; ++f) {
        q.time.push_back(f / 30.0);
        for (int i = 0; i < 3 * N; ++i) q.nodes.push_back(value(size_t(f * 100 + i)));
        for (int i = 0; i < 3 * S; ++i) q.surface.push_back(value(size_t(f * 200 + i)));
      }
      const fs::path p = d / (std::string(res) + ".fsq");
      write_sequence(p.string(), q);
      note(p);
    }
  }
  const DatasetHeader dh = dataset_header();
  auto dataset_frame = [&](int f) {
    DatasetFrame fr;
    fr.time = f / 30.0;
    fr.weights = {0.5f * float(f), 0.25f};
    fr.jaw = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, -0.1f * float(f), 0};
    for (int i = 0; i < 3 * N; ++i) fr.lr_disp.push_back(value(size_t(f * 10 + i)));
    for (int i = 0; i < 3 * S; ++i) fr.hr_disp.push_back(value(size_t(f * 20 + i)));
    for (int i = 0; i < 3 * S; ++i) fr.embedded_disp.push_back(value(size_t(f * 30 + i)));
    fr.stats.hr_newton_iters = 3 + f;
    fr.stats.max_penetration_free_cm = 0.01f;
    return fr;
  };
  {  // .fsd, and the partial file a killed dataset run leaves
    const fs::path d = folder("dataset");
    DatasetSequence s;
    s.header = dh;
    for (int f = 0; f < 2; ++f) s.frames.push_back(dataset_frame(f));
    write_dataset_sequence((d / "tiny.fsd").string(), s);
    note(d / "tiny.fsd");

    const fs::path pd = folder("dataset_partial");
    const fs::path target = pd / "t.fsd";
    {
      DatasetWriter w(target.string(), dh, true);
      for (int f = 0; f < 2; ++f) w.add_frame(dataset_frame(f));
    }  // destroyed without commit: the partial file stays
    const fs::path partial = DatasetWriter::partial_path_for(target.string());
    fs::rename(partial, pd / "two_frames.partial");
    note(pd / "two_frames.partial");
  }
  {  // performance JSON: weights only, and with an explicit jaw
    const fs::path d = folder("performance");
    Performance p;
    p.name = "tiny";
    p.fps = 30;
    p.names = {"jawOpen", "mouthSmile_L", "eyeBlink_R"};
    p.weights = {0, 0, 0, 0.5f, 0.25f, 1, 1, 0.5f, 0};
    save_performance_json(p, (d / "weights.json").string());
    note(d / "weights.json");
    p.has_jaw = true;
    p.jaw = {0, 0, 0, 0, 0, 0, 5, 0, 0, 0, -0.1f, 0, 10, 1, 0, 0, -0.2f, 0.05f};
    save_performance_json(p, (d / "jaw.json").string());
    note(d / "jaw.json");
  }
  {  // Live Link Face CSV: the app's layout, with a tracking-lost row and a
     // clamped weight; then the start of each real take
    const fs::path d = folder("livelink");
    write_text(d / "clock.csv",
               "Timecode,BlendShapeCount,EyeBlinkLeft,JawOpen,MouthSmileRight,CheekPuff,TongueOut,HeadYaw\n"
               "19:35:05:27.466,61,0.0512,0.1203,0.3,0.0,0.0,0.01\n"
               "19:35:05:29.466,61,0.0612,0.2203,0.4,1.04,0.0,0.02\n"
               "19:35:05:31.466,0\n"
               "19:35:06:01.466,61,0.0712,0.3203,0.5,0.1,0.0,0.03\n");
    write_text(d / "seconds.csv", "Timecode,JawOpen,EyeBlinkRight\n0.0,0.1,0.2\n0.05,0.2,0.1\n0.1,0.3,0\n");
    write_text(d / "frames.csv", "Timecode,JawOpen\n0,0.1\n1,0.2\n2,0.3\n4,0.1\n");
    note(d / "clock.csv");
    note(d / "seconds.csv");
    note(d / "frames.csv");
    if (!livelink_dir.empty() && fs::is_directory(livelink_dir)) {
      for (const auto& e : fs::directory_iterator(livelink_dir)) {
        if (e.path().extension() != ".csv") continue;
        std::ifstream in(e.path());
        std::string line, text;
        for (int i = 0; i < 6 && std::getline(in, line); ++i) text += line + "\n";
        const fs::path p = d / ("take_" + e.path().filename().string());
        write_text(p, text);
        note(p);
      }
    }
  }
  {  // OBJ: the tiny surface, and one with normals, texture coordinates and polygons
    const fs::path d = folder("obj");
    write_obj((d / "tiny.obj").string(), r.surface, r.surface_tris);
    note(d / "tiny.obj");
    write_text(d / "quads.obj",
               "# exported\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\n"
               "vn 0 0 1\ng face\nf 1/1/1 2/2/1 3/3/1 4/4/1\nf -4 -3 -2\n");
    note(d / "quads.obj");
  }
  {  // dataset manifest
    const fs::path d = folder("manifest");
    DatasetManifest m;
    m.rig_name = r.name;
    m.rig_checksum = rig_checksum(r);
    m.rig_path = "tiny.rig";
    m.num_lr_nodes = N;
    m.num_surface = S;
    m.weight_names = r.blendshape_names;
    DatasetManifest::Entry a;
    a.name = "tiny";
    a.file = "tiny.fsd";
    a.frames = 2;
    a.complete = true;
    a.hr_mean_step_s = 0.5;
    DatasetManifest::Entry b = a;
    b.name = "test";
    b.file = "test.fsd";
    b.split = "test";
    b.complete = false;
    m.sequences = {a, b};
    m.extra = {{"recipe", "tiny"}};
    save_manifest((d / "manifest.json").string(), m);
    note(d / "manifest.json");
  }
  return written;
}

}  // namespace facesr::tiny
