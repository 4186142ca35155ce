// `facesr model transfer`: a model carried over to another rig keeps its
// weights, recomputes every rig-dependent array, runs on the new rig through
// every inference path alike, and onto its own rig reproduces itself.
#include <gtest/gtest.h>

#include <filesystem>
#include <memory>

#include <nlohmann/json.hpp>

#include "rig/rig_io.h"
#include "runtime/sr_inference.h"
#include "sr/coordinate_frame.h"
#include "sr/model_transfer.h"
#include "sr/sr_model.h"
#include "sr_fixtures.h"
#include "test_support.h"
#include "train/torch_predictor.h"

namespace facesr {
namespace {

using fixtures::error_of;
using fixtures::random_model;

#define EXPECT_HAS(msg, part) EXPECT_NE(std::string(msg).find(part), std::string::npos) << (msg)

// Another face: the procedural head sampled and remeshed more finely, on a
// finer lattice (other vertex and node counts, other positions).
const Rig& other_rig() {
  static const Rig rig = [] {
    const std::string dir = fixtures::shared_cache_dir("procedural_other_rig", [](const std::string& d) {
      RigBuildOptions o = fixtures::coarse_rig_options();
      o.procedural.edge = 0.65;
      o.lr_cell = 1.0;
      std::filesystem::create_directories(d);
      save_rig(build_rig(o), d + "/other.rig");
    });
    return load_rig(dir + "/other.rig");
  }();
  return rig;
}

double max_diff(const torch::Tensor& a, const torch::Tensor& b) { return (a - b).abs().max().item<double>(); }

TEST(ModelTransfer, KeepsTheWeightsAndRecomputesEveryRigDependentArray) {
  const auto m = random_model(true, true, 5, /*embedded_skip=*/true);
  const Rig& to = other_rig();
  ASSERT_NE(to.lr.mesh.X.rows(), m->num_lr) << "the fixture should give the other rig another lattice";
  ModelTransferReport rep;
  const SrModel t = transfer_sr_model(*m, to, rig_checksum(to), &rep, "test");
  EXPECT_EQ(t.rig_checksum, rig_checksum(to));
  EXPECT_EQ(t.num_lr, int(to.lr.mesh.X.rows()));
  EXPECT_EQ(t.num_hr, int(to.surface.rows()));
  ASSERT_EQ(t.tensors.size(), m->tensors.size());
  for (size_t i = 0; i < t.tensors.size(); ++i) {
    EXPECT_EQ(t.tensors[i].name, m->tensors[i].name);
    EXPECT_EQ(t.tensors[i].values, m->tensors[i].values) << t.tensors[i].name;
  }
  EXPECT_EQ(t.arch.input_scale, m->arch.input_scale);
  EXPECT_EQ(t.arch.output_scale, m->arch.output_scale);
  // Every rig-dependent array is the one the new rig gives, and not the old one.
  const SrGeometry fresh = build_sr_geometry(to, {m->geometry.graph_k, m->geometry.upsample_k});
  const SrGeometry& g = t.geometry;
  EXPECT_EQ(g.lr_rest, fresh.lr_rest);
  EXPECT_EQ(g.hr_rest, fresh.hr_rest);
  EXPECT_EQ(g.lr_graph, fresh.lr_graph);
  EXPECT_EQ(g.lr_to_hr, fresh.lr_to_hr);
  EXPECT_EQ(g.up_index, fresh.up_index);
  EXPECT_EQ(g.up_dist, fresh.up_dist);
  EXPECT_EQ(g.embed_nodes, fresh.embed_nodes);
  EXPECT_EQ(g.embed_weights, fresh.embed_weights);
  EXPECT_EQ(g.hr_tris, fresh.hr_tris);
  EXPECT_NE(g.lr_rest.size(), m->geometry.lr_rest.size());
  EXPECT_NE(g.hr_rest.size(), m->geometry.hr_rest.size());
  SrArchitecture frame = t.arch;
  set_coordinate_frame(frame, fresh);
  EXPECT_EQ(t.arch.coord_center, frame.coord_center);
  EXPECT_EQ(t.arch.coord_scale, frame.coord_scale);
  EXPECT_NE(t.arch.coord_scale, m->arch.coord_scale);
  // Each new node takes the encoding of an old node, and the lattices line up
  // to within about a cell once both heads are normalised.
  ASSERT_EQ(g.pe_rows.size(), size_t(t.num_lr));
  for (int32_t r : g.pe_rows) {
    ASSERT_GE(r, 0);
    ASSERT_LT(r, m->num_lr);
  }
  EXPECT_GT(rep.pe_match_mean_cm, 0);
  EXPECT_LT(rep.pe_match_mean_cm, 1.2);
  EXPECT_EQ(rep.to_lr, t.num_lr);
  EXPECT_EQ(rep.from_lr, m->num_lr);
  size_t n = 0;
  for (const auto& x : m->tensors) n += x.values.size();
  EXPECT_EQ(rep.parameters_kept, n);
}

TEST(ModelTransfer, RunsAlikeThroughLibTorchCpuAndOpenClAfterASaveAndLoad) {
  const auto m = random_model(true, true, 6, /*embedded_skip=*/true);
  const Rig& to = other_rig();
  const std::string path = (std::filesystem::temp_directory_path() / "facesr_transfer_test.fsm").string();
  save_sr_model(path, transfer_sr_model(*m, to, rig_checksum(to), nullptr, "test"));
  const auto t = std::make_shared<SrModel>(load_sr_model(path));
  std::filesystem::remove(path);
  EXPECT_FALSE(t->geometry.pe_rows.empty()) << "pe_rows must survive the file";
  const auto lr = fixtures::lr_frames(*t, 2);
  const auto ref = TorchPredictor(*t).predict(lr);
  EXPECT_GT(ref.abs().max().item<double>(), 1e-3);
  auto cpu = make_cpu_inference(t);
  auto cl = make_cl_inference(t);
  for (int f = 0; f < 2; ++f) {
    std::vector<float> a(size_t(3 * t->num_hr)), b(a.size());
    const auto in = lr[f].contiguous();
    cpu->infer(in.data_ptr<float>(), a.data());
    cl->infer(in.data_ptr<float>(), b.data());
    EXPECT_LT(max_diff(torch::from_blob(a.data(), {t->num_hr, 3}), ref[f]), 1e-4) << "CPU, frame " << f;
    EXPECT_LT(max_diff(torch::from_blob(b.data(), {t->num_hr, 3}), ref[f]), 1e-4) << "OpenCL, frame " << f;
  }
  // The encoding matters: the same model with each node's own index gives another output.
  SrModel plain = *t;
  plain.geometry.pe_rows.clear();
  const auto other = TorchPredictor(plain).predict(lr);
  EXPECT_GT(max_diff(other, ref), 1e-4);
}

TEST(ModelTransfer, OntoItsOwnRigReproducesTheModel) {
  const auto m = random_model(true, true, 7, /*embedded_skip=*/true);
  const Rig& rig = fixtures::procedural_rig();
  ModelTransferReport rep;
  const SrModel t = transfer_sr_model(*m, rig, rig_checksum(rig), &rep, "test");
  EXPECT_EQ(rep.pe_match_max_cm, 0);
  for (int i = 0; i < t.num_lr; ++i) ASSERT_EQ(t.geometry.pe_rows[size_t(i)], i);
  const auto lr = fixtures::lr_frames(*m, 2);
  EXPECT_EQ(max_diff(TorchPredictor(t).predict(lr), TorchPredictor(*m).predict(lr)), 0);
}

TEST(ModelTransfer, TransferTwiceComposesTheEncodingRows) {
  const auto m = random_model(true, true, 8);
  const Rig &a = fixtures::procedural_rig(), &b = other_rig();
  const SrModel ab = transfer_sr_model(*m, b, rig_checksum(b), nullptr, "test");
  const SrModel aba = transfer_sr_model(ab, a, rig_checksum(a), nullptr, "test");
  // Back on the first rig every node's row is an index of the first rig's
  // lattice, and most nodes get their own back.
  int own = 0;
  for (int i = 0; i < aba.num_lr; ++i) {
    ASSERT_LT(aba.geometry.pe_rows[size_t(i)], m->num_lr);
    own += aba.geometry.pe_rows[size_t(i)] == i;
  }
  EXPECT_GT(own, aba.num_lr / 2);
}

TEST(ModelTransfer, RefusesModelsSizedByTheirRig) {
  const Rig& to = other_rig();
  const auto free_weights = random_model(true, false, 9);
  EXPECT_HAS(error_of([&] { transfer_sr_model(*free_weights, to, rig_checksum(to), nullptr, "m.fsm"); }),
             "free upsampling weights");
  SrModel vae = *random_model(true, true, 9);
  vae.arch.kind = "vae";
  EXPECT_HAS(error_of([&] { transfer_sr_model(vae, to, rig_checksum(to), nullptr, "m.fsm"); }), "'vae' model");
}

TEST(ModelTransfer, DropsNearRestCorrectivesAndSaysSo) {
  SrModel m = *random_model(true, true, 10, true);
  RestCorrectives& c = m.rest_correctives;
  c.shapes = {"jawOpen"};
  c.amplitudes = {{0.05f}};
  c.lr.assign(size_t(3 * m.num_lr), 0.01f);
  c.hr.assign(size_t(3 * m.num_hr), 0.001f);
  validate_sr_model(m, "fixture");
  const Rig& to = other_rig();
  ModelTransferReport rep;
  const SrModel t = transfer_sr_model(m, to, rig_checksum(to), &rep, "test");
  EXPECT_TRUE(t.rest_correctives.empty());
  EXPECT_EQ(rep.correctives_dropped, 1);
  EXPECT_EQ(rep.to_json()["rest_correctives_dropped"], 1);
  EXPECT_EQ(t.training["transferred"][0]["rest_correctives_dropped"], 1);
}

}  // namespace
}  // namespace facesr
