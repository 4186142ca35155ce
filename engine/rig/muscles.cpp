#include "rig/muscles.h"

#include <algorithm>
#include <cmath>
#include <map>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "core/error.h"
#include "mesh/surface_query.h"

namespace facesr::rig_embedded {
const std::map<std::string, std::string>& embedded_files();
}

namespace facesr {
namespace {
using nlohmann::json;

std::string mirror(const std::string& n) {
  auto swap_suffix = [](const std::string& s) {
    if (s.size() > 2 && s.compare(s.size() - 2, 2, "_L") == 0) return s.substr(0, s.size() - 2) + "_R";
    if (s.size() > 2 && s.compare(s.size() - 2, 2, "_R") == 0) return s.substr(0, s.size() - 2) + "_L";
    return s;
  };
  // Ring landmark names carry the side in the middle: eye_ring_L_3.
  for (const char* mid : {"_L_", "_R_"}) {
    const auto pos = n.find(mid);
    if (pos != std::string::npos) {
      std::string out = n;
      out[pos + 1] = mid[1] == 'L' ? 'R' : 'L';
      return out;
    }
  }
  return swap_suffix(n);
}

// Centripetal-free uniform Catmull-Rom through control points; closed loops
// wrap around. Lines with two points stay straight.
Points sample_curve(const std::vector<Vec3>& c, bool closed, int per_segment) {
  std::vector<Vec3> out;
  const int n = int(c.size());
  auto at = [&](int i) {
    if (closed) return c[((i % n) + n) % n];
    return c[std::clamp(i, 0, n - 1)];
  };
  const int segs = closed ? n : n - 1;
  for (int s = 0; s < segs; ++s)
    for (int k = 0; k < per_segment; ++k) {
      const double t = double(k) / per_segment;
      const Vec3 p0 = at(s - 1), p1 = at(s), p2 = at(s + 1), p3 = at(s + 2);
      const double t2 = t * t, t3 = t2 * t;
      out.push_back(0.5 * (2 * p1 + (-p0 + p2) * t + (2 * p0 - 5 * p1 + 4 * p2 - p3) * t2 +
                           (-p0 + 3 * p1 - 3 * p2 + p3) * t3));
    }
  if (!closed) out.push_back(c.back());
  else out.push_back(out.front());  // explicit closing segment
  Points P(long(out.size()), 3);
  for (size_t i = 0; i < out.size(); ++i) P.row(long(i)) = out[i].transpose();
  return P;
}
}  // namespace

const std::string& default_muscle_spec() {
  static const std::string spec = rig_embedded::embedded_files().at("muscles.json");
  return spec;
}

MuscleSet build_muscles(const std::string& text, const std::string& spec_name, const HeadSource& src,
                        const SurfaceQuery& skin) {
  json spec;
  try {
    spec = json::parse(text);
  } catch (const std::exception& e) {
    throw Error(spec_name + ": malformed JSON (" + e.what() + ")");
  }
  require(spec.value("format", "") == "facesr-muscles", spec_name + ": not a facesr-muscles file");
  require(spec.value("version", 0) == 1, spec_name + ": unsupported version (expected 1)");
  auto landmark = [&](const std::string& name) -> Vec3 {
    auto it = src.landmarks.find(name);
    require(it != src.landmarks.end(), spec_name + ": landmark '" + name + "' is not defined on head '" + src.name + "'");
    return src.skin.V.row(it->second).transpose();
  };
  const double ref = spec.value("reference_eye_distance_cm", 9.0);
  const double scale = (landmark("eye_outer_L") - landmark("eye_outer_R")).norm() / ref;
  // Inward placement: project to the skin, then move against the face normal.
  auto place = [&](const Vec3& q, double depth) {
    const auto c = skin.closest(q);
    const auto& V = src.skin.V;
    const auto& F = src.skin.F;
    const Vec3 a = V.row(F(c.tri, 0)), b = V.row(F(c.tri, 1)), d = V.row(F(c.tri, 2));
    const Vec3 n = (b - a).cross(d - a).normalized();
    return Vec3(c.point - depth * n);
  };
  MuscleSet out;
  for (const auto& m : spec.at("muscles")) {
    const std::string base = m.at("name");
    const std::string type = m.value("type", "line");
    require(type == "line" || type == "sphincter", spec_name + ": muscle '" + base + "' has unknown type '" + type + "'");
    const bool mirrored = m.value("mirror", false);
    const double radius = m.at("radius").get<double>() * scale;
    const double depth = m.at("depth").get<double>() * scale;
    require(radius > 0 && depth >= 0, spec_name + ": muscle '" + base + "' needs radius > 0 and depth >= 0");
    for (int side = 0; side < (mirrored ? 2 : 1); ++side) {
      const double sx = side == 0 ? 1.0 : -1.0;
      auto lm = [&](const std::string& n) { return side == 0 ? n : mirror(n); };
      Muscle mu;
      mu.name = mirrored ? base + (side == 0 ? "_L" : "_R") : base;
      mu.radius = radius;
      std::vector<Vec3> ctrl;
      if (type == "line") {
        mu.type = MuscleType::Line;
        for (const auto& p : m.at("path")) {
          const auto off = p.value("offset", std::vector<double>{0, 0, 0});
          require(off.size() == 3, spec_name + ": muscle '" + base + "' offset must have 3 numbers");
          const Vec3 o(sx * off[0] * scale, off[1] * scale, off[2] * scale);
          ctrl.push_back(place(landmark(lm(p.at("landmark"))) + o, depth));
        }
        require(ctrl.size() >= 2, spec_name + ": line muscle '" + base + "' needs >= 2 path points");
      } else {
        mu.type = MuscleType::Sphincter;
        std::vector<Vec3> ring;
        for (const auto& n : m.at("ring")) ring.push_back(landmark(lm(n)));
        require(ring.size() >= 3, spec_name + ": sphincter '" + base + "' needs >= 3 ring landmarks");
        Vec3 c = Vec3::Zero();
        for (const auto& p : ring) c += p;
        c /= double(ring.size());
        const double rs = m.value("ring_scale", 1.0);
        for (const auto& p : ring) ctrl.push_back(place(c + rs * (p - c), depth));
      }
      mu.curve = sample_curve(ctrl, mu.type == MuscleType::Sphincter, 8);
      out.muscles.push_back(std::move(mu));
    }
  }
  // Activation table.
  const int nm = int(out.muscles.size());
  const int nb = int(src.blendshape_names.size());
  out.activation.assign(size_t(nb) * nm, 0.0f);
  auto muscle_index = [&](const std::string& n) {
    for (int i = 0; i < nm; ++i)
      if (out.muscles[i].name == n) return i;
    throw Error(spec_name + ": activation refers to unknown muscle '" + n + "'");
  };
  auto set = [&](const std::string& shape, const std::string& muscle, double a) {
    const int mi = muscle_index(muscle);
    for (int b = 0; b < nb; ++b)
      if (src.blendshape_names[b] == shape) out.activation[size_t(b) * nm + mi] = float(a);
  };
  if (spec.contains("activations")) {
    for (const auto& [shape, table] : spec["activations"].items()) {
      for (const auto& [muscle, a] : table.items()) {
        const double v = a.get<double>();
        require(std::isfinite(v) && v >= 0 && v <= 1, spec_name + ": activation " + shape + " -> " + muscle + " must be in [0, 1]");
        set(shape, muscle, v);
        if (shape.size() > 2 && shape.compare(shape.size() - 2, 2, "_L") == 0) set(mirror(shape), mirror(muscle), v);
      }
    }
  }
  return out;
}

double muscle_distance(const Muscle& m, const Vec3& p, Vec3* fibre) {
  double best = 1e300;
  Vec3 dir = Vec3::UnitX();
  for (int i = 0; i + 1 < m.curve.rows(); ++i) {
    const Vec3 a = m.curve.row(i), b = m.curve.row(i + 1);
    const Vec3 ab = b - a;
    const double L2 = ab.squaredNorm();
    if (L2 <= 0) continue;
    const double t = std::clamp((p - a).dot(ab) / L2, 0.0, 1.0);
    const double d = (a + t * ab - p).squaredNorm();
    if (d < best) best = d, dir = ab / std::sqrt(L2);
  }
  if (fibre) *fibre = dir;
  return std::sqrt(best);
}

void rasterize_muscles(const std::vector<Muscle>& muscles, int samples, const std::function<Vec3(const Vec3&)>& to_rest,
                       const std::function<bool(const Vec3&)>& in_flesh, SimMesh& sm) {
  const auto& X = sm.mesh.X;
  const auto& T = sm.mesh.T;
  const int nt = int(T.rows());
  sm.muscle.assign(nt, -1);
  sm.muscle_fraction.assign(nt, 0.0f);
  sm.fibre.assign(size_t(nt) * 3, 0.0f);
  // Sample points as barycentric weights: a regular barycentric lattice pulled
  // slightly toward the centroid so no sample sits on a shared face.
  std::vector<Vec4> bary;
  const int n = samples <= 5 ? 1 : 3;
  if (n == 1) {
    bary.push_back(Vec4::Constant(0.25));
    for (int k = 0; k < 4; ++k) {
      Vec4 b = Vec4::Constant(0.55 * 0.25);
      b[k] += 0.45;
      bary.push_back(b);
    }
  } else {
    for (int i = 0; i <= n; ++i)
      for (int j = 0; i + j <= n; ++j)
        for (int k = 0; i + j + k <= n; ++k) {
          const Vec4 b(i, j, k, n - i - j - k);
          bary.push_back(0.85 * b / n + 0.15 * Vec4::Constant(0.25));
        }
  }
  std::vector<Vec3> lo(muscles.size()), hi(muscles.size());
  for (size_t m = 0; m < muscles.size(); ++m) {
    lo[m] = muscles[m].curve.colwise().minCoeff().transpose() - Vec3::Constant(muscles[m].radius);
    hi[m] = muscles[m].curve.colwise().maxCoeff().transpose() + Vec3::Constant(muscles[m].radius);
  }
#pragma omp parallel for schedule(dynamic, 256)
  for (int t = 0; t < nt; ++t) {
    std::vector<int> count(muscles.size(), 0);
    std::vector<Vec3> dir(muscles.size(), Vec3::Zero());
    for (const auto& b : bary) {
      Vec3 p = Vec3::Zero();
      for (int k = 0; k < 4; ++k) p += b[k] * Vec3(X.row(T(t, k)));
      const Vec3 r = to_rest(p);
      bool checked = false, flesh = false;
      for (size_t m = 0; m < muscles.size(); ++m) {
        if ((r.array() < lo[m].array()).any() || (r.array() > hi[m].array()).any()) continue;
        Vec3 f;
        if (muscle_distance(muscles[m], r, &f) > muscles[m].radius) continue;
        if (!checked) flesh = in_flesh(r), checked = true;
        if (!flesh) break;
        count[m]++;
        // Fibres are lines, not vectors: align signs before averaging.
        dir[m] += f.dot(dir[m]) < 0 ? -f : f;
      }
    }
    const auto best = std::max_element(count.begin(), count.end());
    if (best != count.end() && *best > 0) {
      const int m = int(best - count.begin());
      sm.muscle[t] = m;
      sm.muscle_fraction[t] = float(double(*best) / double(bary.size()));
      const Vec3 d = dir[m].normalized();
      for (int k = 0; k < 3; ++k) sm.fibre[size_t(t) * 3 + k] = float(d[k]);
    }
  }
}

}  // namespace facesr
