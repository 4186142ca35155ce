#include "sr/sr_architecture.h"

#include <cmath>

#include "core/error.h"
#include "core/json_fields.h"

namespace facesr {

using nlohmann::json;
using namespace json_fields;

int SrArchitecture::encoded_dim() const {
  int d = input_dim();
  if (feature_encoding)
    for (int e : encoder_dims) d += e;
  return d;
}

json architecture_to_json(const SrArchitecture& a) {
  return {{"kind", a.kind},
          {"pe_dim", a.pe_dim},
          {"encoder_dims", a.encoder_dims},
          {"graph_k", a.graph_k},
          {"upsample_k", a.upsample_k},
          {"feature_encoding", a.feature_encoding},
          {"coordinate_upsampling", a.coordinate_upsampling},
          {"embedded_skip", a.embedded_skip}, {"zero_rest", a.zero_rest},
          {"weight_hidden", a.weight_hidden},
          {"recon_hidden", a.recon_hidden},
          {"omega0", a.omega0},
          {"leaky_slope", a.leaky_slope},
          {"vae_encoder", a.vae_encoder},
          {"vae_latent", a.vae_latent},
          {"vae_decoder", a.vae_decoder},
          {"input_scale", a.input_scale},
          {"output_scale", a.output_scale},
          {"coord_center", a.coord_center},
          {"coord_scale", a.coord_scale}};
}

namespace {
void require_nonempty(const std::vector<int>& v, const std::string& at, const char* key) {
  require(!v.empty(), at + key + " is empty");
}
double positive(const json& j, const char* key, const std::string& at) {
  const double v = number_field(j, key, at);
  require(v > 0, at + key + " is " + std::to_string(v) + ", expected > 0");
  return v;
}
}  // namespace

SrArchitecture architecture_from_json(const json& j, const std::string& source) {
  const std::string at = source + ": architecture.";
  require(j.is_object(), source + ": architecture is not an object");
  SrArchitecture a;
  a.kind = string_field(j, "kind", at);
  require(a.kind == "sr" || a.kind == "vae", at + "kind is '" + a.kind + "', expected 'sr' or 'vae'");
  a.pe_dim = int_field(j, "pe_dim", at, 0);
  require(a.pe_dim % 2 == 0 && a.pe_dim <= 1024, at + "pe_dim must be even and at most 1024");
  a.encoder_dims = int_list_field(j, "encoder_dims", at, 1);
  a.graph_k = int_field(j, "graph_k", at, 1);
  a.upsample_k = int_field(j, "upsample_k", at, 1);
  require(a.graph_k <= 64 && a.upsample_k <= 64, at + "graph_k and upsample_k must be at most 64");
  a.feature_encoding = bool_field(j, "feature_encoding", at);
  a.coordinate_upsampling = bool_field(j, "coordinate_upsampling", at);
  a.embedded_skip = j.contains("embedded_skip") && bool_field(j, "embedded_skip", at);
  a.zero_rest = j.contains("zero_rest") && bool_field(j, "zero_rest", at);
  a.weight_hidden = int_list_field(j, "weight_hidden", at, 1);
  a.recon_hidden = int_list_field(j, "recon_hidden", at, 1);
  require_nonempty(a.recon_hidden, at, "recon_hidden");
  if (a.coordinate_upsampling) require_nonempty(a.weight_hidden, at, "weight_hidden");
  if (a.feature_encoding && a.kind == "sr") require_nonempty(a.encoder_dims, at, "encoder_dims");
  a.omega0 = positive(j, "omega0", at);
  a.leaky_slope = number_field(j, "leaky_slope", at);
  require(a.leaky_slope >= 0 && a.leaky_slope < 1, at + "leaky_slope must be in [0, 1)");
  a.vae_encoder = int_list_field(j, "vae_encoder", at, 1);
  a.vae_latent = int_field(j, "vae_latent", at, 1);
  a.vae_decoder = int_list_field(j, "vae_decoder", at, 1);
  a.input_scale = positive(j, "input_scale", at);
  a.output_scale = positive(j, "output_scale", at);
  const json& c = field(j, "coord_center", at);
  require(c.is_array() && c.size() == 3, at + "coord_center is not an array of 3 numbers");
  for (int i = 0; i < 3; ++i) {
    require(c[i].is_number() && std::isfinite(c[i].get<double>()), at + "coord_center has a non-number");
    a.coord_center[i] = c[i].get<double>();
  }
  a.coord_scale = positive(j, "coord_scale", at);
  return a;
}

std::vector<std::pair<std::string, std::vector<int64_t>>> parameter_shapes(const SrArchitecture& a, int N, int M) {
  std::vector<std::pair<std::string, std::vector<int64_t>>> out;
  auto linear = [&](const std::string& name, int64_t in, int64_t outd) {
    out.push_back({name + ".weight", {outd, in}});
    out.push_back({name + ".bias", {outd}});
  };
  if (a.kind == "vae") {
    int64_t in = 3 * int64_t(N);
    for (size_t l = 0; l < a.vae_encoder.size(); ++l) {
      linear("encoder." + std::to_string(l), in, a.vae_encoder[l]);
      in = a.vae_encoder[l];
    }
    linear("mu", in, a.vae_latent);
    linear("logvar", in, a.vae_latent);
    in = a.vae_latent;
    for (size_t l = 0; l < a.vae_decoder.size(); ++l) {
      linear("decoder." + std::to_string(l), in, a.vae_decoder[l]);
      in = a.vae_decoder[l];
    }
    linear("out", in, 3 * int64_t(M));
    return out;
  }
  if (a.feature_encoding) {
    int64_t in = a.input_dim();
    for (size_t s = 0; s < a.encoder_dims.size(); ++s) {
      const int64_t d = a.encoder_dims[s];
      const std::string p = "encoder." + std::to_string(s);
      linear(p + ".edge", 2 * in, d);
      linear(p + ".fc", 3 * d + in, d);
      in = d;
    }
  }
  if (a.coordinate_upsampling) {
    int64_t in = 7;
    for (size_t l = 0; l < a.weight_hidden.size(); ++l) {
      linear("weight_net." + std::to_string(l), in, a.weight_hidden[l]);
      in = a.weight_hidden[l];
    }
    linear("weight_net." + std::to_string(a.weight_hidden.size()), in, 1);
  } else {
    out.push_back({"free_weights", {int64_t(M), int64_t(a.upsample_k)}});
  }
  int64_t in = a.encoded_dim();
  for (size_t l = 0; l < a.recon_hidden.size(); ++l) {
    linear("recon." + std::to_string(l), in, a.recon_hidden[l]);
    in = a.recon_hidden[l];
  }
  linear("recon." + std::to_string(a.recon_hidden.size()), in, 3);
  return out;
}

}  // namespace facesr
