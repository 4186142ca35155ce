// `facesr model`: inspect a trained model file, set zero_rest on one after
// training (how the shipped ICT model was made: see docs/network.md), and
// carry a model over to a rebuilt rig whose geometry it still matches, and
// blend the weights of two fine-tunes of one model, smooth what it adds to
// the embedded surface, and measure its near-rest correctives on a dataset.
#include <algorithm>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "commands.h"
#include "core/error.h"
#include "core/framed_file.h"
#include "rig/rig_io.h"
#include "postfit/fit_rest_correctives.h"
#include "sr/model_transfer.h"
#include "sr/sr_geometry_compare.h"
#include "sr/sr_model.h"
#include "sr/sr_model_blend.h"

namespace facesr::cli {

namespace {

nlohmann::json model_summary(const SrModel& m, const std::string& path) {
  size_t parameters = 0;
  for (const auto& t : m.tensors) parameters += t.values.size();
  return {{"model", path},          {"kind", m.arch.kind},          {"rig_name", m.rig_name},
          {"num_lr", m.num_lr},     {"num_hr", m.num_hr},           {"parameters", parameters},
          {"zero_rest", m.arch.zero_rest}, {"embedded_skip", m.arch.embedded_skip},
          {"rest_correctives", m.rest_correctives.count()},
          {"residual_smoothing", m.residual_smoothing.empty() ? nlohmann::json(nullptr)
                                                              : residual_smoothing_to_json(m.residual_smoothing)},
          {"units", "cm"}};
}

}  // namespace

void register_model(CLI::App& app) {
  auto* model = app.add_subcommand("model", "Inspect or adjust a trained model file (.fsm)");
  model->require_subcommand(1);

  struct InfoArgs {
    std::string path;
    bool json = false;
  };
  static InfoArgs info;
  auto* i = model->add_subcommand("info", "Print a model file's architecture and rig");
  i->add_option("model", info.path, "Model file (.fsm)")->required();
  i->add_flag("--json", info.json, "Print a JSON summary: kind, rig_name, num_lr, num_hr, parameters, zero_rest, embedded_skip");
  add_action(i, [] {
    const SrModel m = load_sr_model(info.path);
    const auto s = model_summary(m, info.path);
    if (info.json)
      std::printf("%s\n", s.dump(2).c_str());
    else
      std::printf("%s: '%s' model for rig '%s' (%d LR nodes, %d HR vertices), %zu parameters, zero_rest %s\n",
                  info.path.c_str(), m.arch.kind.c_str(), m.rig_name.c_str(), m.num_lr, m.num_hr,
                  s["parameters"].get<size_t>(), m.arch.zero_rest ? "on" : "off");
  });

  struct ZeroRestArgs {
    std::string in, out;
    bool json = false;
  };
  static ZeroRestArgs zr;
  auto* z = model->add_subcommand(
      "zero-rest",
      "Write a copy whose output at the rest input is subtracted (rest maps exactly to rest; not in the paper)");
  z->add_option("model", zr.in, "Trained model file (.fsm, kind sr)")->required();
  z->add_option("-o,--out", zr.out, "Output model file")->required();
  z->add_flag("--json", zr.json, "Print a JSON summary of the written model");
  add_action(z, [] {
    SrModel m = load_sr_model(zr.in);
    require(m.arch.kind == "sr", zr.in + ": zero-rest applies to the super-resolution network, not to a '" +
                                     m.arch.kind + "' model");
    require(!m.arch.zero_rest, zr.in + ": zero_rest is already set");
    m.arch.zero_rest = true;
    m.training["zero_rest_added_after_training"] = true;
    save_sr_model(zr.out, m);  // written to a temporary name, then renamed
    if (zr.json) std::printf("%s\n", model_summary(m, zr.out).dump(2).c_str());
  });

  struct RebindArgs {
    std::string rig, in, out;
    double tolerance_cm = 1e-5;
    bool json = false;
  };
  static RebindArgs rb;
  auto* b = model->add_subcommand(
      "rebind",
      "Write a copy bound to a rebuilt rig, after checking that the rig gives the rest poses, neighbourhoods and "
      "embedding the model was trained with");
  b->add_option("model", rb.in, "Trained model file (.fsm)")->required();
  b->add_option("--rig", rb.rig, "The rebuilt rig (.rig)")->required();
  b->add_option("-o,--out", rb.out, "Output model file")->required();
  b->add_option("--tolerance", rb.tolerance_cm,
                "Largest difference allowed in positions and distances (cm) and in embedding weights")
      ->check(CLI::PositiveNumber);
  b->add_flag("--json", rb.json,
              "Print a JSON summary: from_checksum, to_checksum, max_position_cm, max_distance_cm, max_weight");
  add_action(b, [] {
    SrModel m = load_sr_model(rb.in);
    const Rig rig = load_rig(rb.rig);
    const std::string what = rb.in + " and " + rb.rig;
    require(m.rig_name == rig.name, what + ": the model belongs to rig '" + m.rig_name + "', not '" + rig.name + "'");
    const uint64_t to = rig_checksum(rig);
    require(m.rig_checksum != to, what + ": the model is already bound to this rig");
    const SrGeometry now = build_sr_geometry(rig, {m.geometry.graph_k, m.geometry.upsample_k});
    const SrGeometryDifference d = compare_sr_geometry(m.geometry, now);
    require(d.topology_mismatch.empty(), what + ": the rig's " + d.topology_mismatch +
                                             " differs from the model's; retrain the model for this rig");
    const double worst = std::max({d.max_position_cm, d.max_distance_cm, d.max_weight});
    require(worst <= rb.tolerance_cm, what + ": rest poses differ by up to " + std::to_string(d.max_position_cm) +
                                          " cm, distances by " + std::to_string(d.max_distance_cm) +
                                          " cm, embedding weights by " + std::to_string(d.max_weight) +
                                          ", more than --tolerance " + std::to_string(rb.tolerance_cm));
    const nlohmann::json record = {{"from_checksum", hex64(m.rig_checksum)},
                                   {"to_checksum", hex64(to)},
                                   {"max_position_cm", d.max_position_cm},
                                   {"max_distance_cm", d.max_distance_cm},
                                   {"max_weight", d.max_weight}};
    m.training["rebound"].push_back(record);
    m.rig_checksum = to;
    save_sr_model(rb.out, m);  // written to a temporary name, then renamed
    if (rb.json) {
      auto s = model_summary(m, rb.out);
      s.update(record);
      std::printf("%s\n", s.dump(2).c_str());
    } else {
      std::printf("%s: bound to %s (%s; rest poses within %.3g cm)\n", rb.out.c_str(), rb.rig.c_str(),
                  hex64(to).c_str(), d.max_position_cm);
    }
  });

  struct TransferArgs {
    std::string rig, in, out, encoding = "nearest";
    bool json = false;
  };
  static TransferArgs tr;
  auto* t = model->add_subcommand(
      "transfer",
      "Write a copy for another rig (another face): graphs, neighbourhoods, upsampling inputs, embedding, rest poses, "
      "coordinate frame and per-node positional encodings recomputed for it, the network's weights kept; near-rest "
      "correctives dropped (fit them again on the new rig's data)");
  t->add_option("model", tr.in, "Trained model file (.fsm, kind sr with coordinate-based upsampling)")->required();
  t->add_option("--rig", tr.rig, "The rig to carry the model to (.rig)")->required();
  t->add_option("-o,--out", tr.out, "Output model file")->required();
  t->add_option("--node-encoding", tr.encoding,
                "nearest (default): each new LR node takes the positional encoding of the old node nearest to it; "
                "index: its own index, as a model trained on the new rig would (an ablation)")
      ->check(CLI::IsMember({"nearest", "index"}));
  t->add_flag("--json", tr.json,
              "Print a JSON summary: from_rig, to_rig, checksums, sizes, parameters_kept, recomputed, kept, "
              "rest_correctives_dropped, pe_match_mean_cm, pe_match_max_cm");
  add_action(t, [] {
    const SrModel m = load_sr_model(tr.in);
    const Rig rig = load_rig(tr.rig);
    ModelTransferReport rep;
    SrModel out = transfer_sr_model(m, rig, rig_checksum(rig), &rep, tr.in + " to " + tr.rig);
    if (tr.encoding == "index") out.geometry.pe_rows.clear();
    out.training["transferred"].back()["node_encoding"] = tr.encoding;
    save_sr_model(tr.out, out);  // written to a temporary name, then renamed
    if (tr.json) {
      auto s = model_summary(out, tr.out);
      s.update(rep.to_json());
      s["node_encoding"] = tr.encoding;
      std::printf("%s\n", s.dump(2).c_str());
    } else {
      std::printf("%s: '%s' (%d LR nodes, %d HR vertices) carried to '%s' (%d, %d), %zu weights kept, lattices "
                  "matched within %.3g cm on average%s\n",
                  tr.out.c_str(), rep.from_rig.c_str(), rep.from_lr, rep.from_hr, rep.to_rig.c_str(), rep.to_lr,
                  rep.to_hr, rep.parameters_kept, rep.pe_match_mean_cm,
                  rep.correctives_dropped ? (", " + std::to_string(rep.correctives_dropped) +
                                             " near-rest correctives dropped").c_str()
                                          : "");
    }
  });

  struct BlendArgs {
    std::string a, b, out;
    double t = 0.5;
    bool json = false;
  };
  static BlendArgs bl;
  auto* m = model->add_subcommand(
      "blend",
      "Write a model whose weights are (1 - t)·A + t·B, for two fine-tunes of one model (same architecture, rig and "
      "geometry; not in the paper)");
  m->add_option("a", bl.a, "First model file (.fsm)")->required();
  m->add_option("b", bl.b, "Second model file (.fsm)")->required();
  m->add_option("-t", bl.t, "Blend factor in [0, 1] (default 0.5): 0 gives A, 1 gives B");
  m->add_option("-o,--out", bl.out, "Output model file")->required();
  m->add_flag("--json", bl.json, "Print a JSON summary of the written model, with t");
  add_action(m, [] {
    const SrModel a = load_sr_model(bl.a), b = load_sr_model(bl.b);
    const SrModel out = blend_sr_models(a, b, bl.t, bl.a + " and " + bl.b);
    save_sr_model(bl.out, out);  // written to a temporary name, then renamed
    if (bl.json) {
      auto s = model_summary(out, bl.out);
      s["t"] = bl.t;
      std::printf("%s\n", s.dump(2).c_str());
    } else {
      std::printf("%s: (1 - %g)·%s + %g·%s\n", bl.out.c_str(), bl.t, bl.a.c_str(), bl.t, bl.b.c_str());
    }
  });

  struct SmoothArgs {
    std::string in, out;
    ResidualSmoothing s;
    bool json = false;
  };
  static SmoothArgs sm;
  auto* sub = model->add_subcommand(
      "smooth",
      "Write a copy that smooths what the network adds to the embedded surface: K umbrella steps of size lambda "
      "over the surface's edges (not in the paper; see docs/network.md)");
  sub->add_option("model", sm.in, "Trained model file (.fsm, kind sr, with the embedded skip)")->required();
  sub->add_option("--lambda", sm.s.lambda, "Step size in (0, 1] (default 0.5)");
  sub->add_option("--iterations", sm.s.iterations, "Steps K (0 removes the smoothing)")->required();
  sub->add_option("-o,--out", sm.out, "Output model file")->required();
  sub->add_flag("--json", sm.json,
                "Print a JSON summary of the written model (residual_smoothing: lambda, iterations)");
  add_action(sub, [] {
    validate_residual_smoothing(sm.s, "model smooth");
    SrModel m = load_sr_model(sm.in);
    require(m.arch.kind == "sr" && m.arch.embedded_skip,
            sm.in + ": residual smoothing applies to the super-resolution network with the embedded skip");
    // Correctives measure what the output before them misses; smoothing changes it.
    require(m.rest_correctives.empty(), sm.in + ": the model has near-rest correctives, fitted without this "
                                                "smoothing; smooth the model they were fitted to, then fit them again "
                                                "(`facesr model correctives`)");
    m.residual_smoothing = sm.s;
    m.training["residual_smoothing"] = residual_smoothing_to_json(sm.s);
    save_sr_model(sm.out, m);  // written to a temporary name, then renamed
    if (sm.json)
      std::printf("%s\n", model_summary(m, sm.out).dump(2).c_str());
    else
      std::printf("%s: residual smoothing, %d steps of %g\n", sm.out.c_str(), sm.s.iterations, sm.s.lambda);
  });

  struct CorrectiveArgs {
    std::string in, out, dataset;
    RestCorrectiveFitOptions opt;
    bool json = false;
  };
  static CorrectiveArgs rc;
  auto* c = model->add_subcommand(
      "correctives",
      "Write a copy with near-rest correctives: the model's residual on the dataset's training frames that have one "
      "shape alone at a small weight, interpolated between those weights (not in the paper; see docs/network.md)");
  c->add_option("model", rc.in, "Trained model file (.fsm, kind sr); any correctives it has are replaced")
      ->required();
  c->add_option("--dataset", rc.dataset, "Dataset folder (from `facesr dataset`) with single-shape frames")
      ->required();
  c->add_option("-o,--out", rc.out, "Output model file")->required();
  c->add_option("--validation-every", rc.opt.validation_every,
                "Frames held out as in `facesr train` (every n-th training frame; 0: none): never used here");
  c->add_option("--max-weight", rc.opt.max_weight,
                "Largest weight of a shape still counted as near rest (default 0.1; samples also stay <= fade / 2)")
      ->check(CLI::PositiveNumber);
  c->add_option("--fade", rc.opt.fade,
                "Norm of the shape coefficients at which the correction falls to 1/e (quartic fade; default 0.2)")
      ->check(CLI::PositiveNumber);
  c->add_option("--ridge", rc.opt.ridge,
                "Ridge term of the coefficient solve, relative to the mean of diag(DᵀD) (default 1e-3)")
      ->check(CLI::PositiveNumber);
  c->add_flag("--json", rc.json,
              "Print a JSON summary: rest_correctives (shape count), samples, shapes (per shape its samples: "
              "sequence, frame, weight, network_error_cm, corrected_error_cm), unmeasured, fade, ridge");
  add_action(c, [] {
    SrModel m = load_sr_model(rc.in);
    RestCorrectiveFit fit = fit_rest_correctives(m, rc.dataset, rc.opt);
    m.rest_correctives = std::move(fit.correctives);
    m.training["rest_correctives"] = {{"dataset", rc.dataset},
                                      {"validation_every", rc.opt.validation_every},
                                      {"max_weight", rc.opt.max_weight},
                                      {"shapes", fit.shapes}};
    save_sr_model(rc.out, m);  // written to a temporary name, then renamed
    if (rc.json) {
      auto s = model_summary(m, rc.out);
      s["samples"] = m.rest_correctives.samples();
      s["shapes"] = fit.shapes;
      s["unmeasured"] = fit.unmeasured;
      s["fade"] = m.rest_correctives.fade;
      s["ridge"] = m.rest_correctives.ridge;
      std::printf("%s\n", s.dump(2).c_str());
    } else {
      std::printf("%s: near-rest correctives for %d shapes, %d samples (%zu shapes never alone at a small weight in "
                  "the training frames), fade %g\n",
                  rc.out.c_str(), m.rest_correctives.count(), m.rest_correctives.samples(), fit.unmeasured.size(),
                  m.rest_correctives.fade);
    }
  });
}

}  // namespace facesr::cli
