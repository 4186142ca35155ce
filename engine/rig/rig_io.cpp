#include "rig/rig_io.h"

#include <array>
#include <cmath>
#include <cstring>
#include <ostream>
#include <type_traits>

#include "core/atomic_file.h"
#include "core/binary_io.h"
#include "core/checksum.h"
#include "core/error.h"
#include "core/number_text.h"
#include "rig/jaw_fit.h"

namespace facesr {

namespace {

constexpr std::array<char, 8> kMagic = {'F', 'A', 'C', 'E', 'S', 'R', 'I', 'G'};
constexpr uint32_t kVersion = 1;
constexpr size_t kHeaderBytes = 24;
constexpr size_t kChecksumBytes = 8;

// The payload layout, written once and used for both directions so the writer
// and the reader cannot drift apart. `R` is `const Rig` when writing.
template <class IO, class R>
void visit_rig(IO& io, R& rig) {
  auto tri_mesh = [&](auto& m, const std::string& p) {
    io(m.V, p + ".V");
    io(m.F, p + ".F");
  };
  auto sim_mesh = [&](auto& s, const std::string& p) {
    io(s.mesh.X, p + ".mesh.X");
    io(s.mesh.T, p + ".mesh.T");
    io(s.muscle, p + ".muscle");
    io(s.muscle_fraction, p + ".muscle_fraction");
    io(s.fibre, p + ".fibre");
    io(s.dirichlet, p + ".dirichlet");
    io(s.dirichlet_bone, p + ".dirichlet_bone");
    io(s.surface.tet, p + ".surface.tet");
    io(s.surface.weights, p + ".surface.weights");
    io(s.surface.outside, p + ".surface.outside");
    io(s.tracks, p + ".tracks");
    io(s.track_area, p + ".track_area");
  };

  io(rig.name, "name");
  io(rig.units, "units");
  io(rig.surface, "surface");
  io(rig.surface_tris, "surface_tris");
  io(rig.surface_source_vertex, "surface_source_vertex");
  io(rig.blendshape_names, "blendshape_names");
  io(rig.blendshape_deltas, "blendshape_deltas");
  io(rig.landmark_names, "landmark_names");
  io(rig.landmark_vertex, "landmark_vertex");

  io(rig.jaw.pivot, "jaw.pivot");
  io(rig.jaw.axis, "jaw.axis");
  io(rig.jaw.open_angle_deg, "jaw.open_angle_deg");
  io(rig.jaw.hinge_max_error_cm, "jaw.hinge_max_error_cm");
  io.items(rig.jaw.shapes, "jaw.shapes");
  for (auto& s : rig.jaw.shapes) {
    io(s.name, "jaw.shapes.name");
    io(s.R, "jaw.shapes.R");
    io(s.t, "jaw.shapes.t");
    io(s.fit_rms_cm, "jaw.shapes.fit_rms_cm");
  }

  io.items(rig.muscles, "muscles");
  for (auto& m : rig.muscles) {
    io(m.name, "muscles.name");
    io.muscle_type(m.type, "muscles.type");
    io(m.curve, "muscles.curve");
    io(m.radius, "muscles.radius");
  }
  io(rig.activation, "activation");

  tri_mesh(rig.teeth_upper, "teeth_upper");
  tri_mesh(rig.teeth_lower, "teeth_lower");
  sim_mesh(rig.hr, "hr");
  sim_mesh(rig.lr, "lr");

  io(rig.lattice.origin, "lattice.origin");
  io(rig.lattice.cell, "lattice.cell");
  io(rig.lattice.dims, "lattice.dims");

  io(rig.predeform.angle_deg, "predeform.angle_deg");
  io(rig.predeform.surface_jaw_weight, "predeform.surface_jaw_weight");
  io(rig.predeform.surface_predeformed, "predeform.surface_predeformed");

  io(rig.build_seconds, "build_seconds");
  io(rig.source, "source");
}

class PayloadWriter {
 public:
  template <class T, std::enable_if_t<std::is_arithmetic<T>::value, int> = 0>
  void operator()(T v, const std::string&) { w_.put(v); }
  void operator()(const std::array<int32_t, 3>& a, const std::string&) { w_.put(a); }
  void operator()(const std::string& s, const std::string&) { w_.put_string(s); }
  template <class T>
  void operator()(const std::vector<T>& v, const std::string&) { w_.put_vector(v); }
  void operator()(const std::vector<std::string>& v, const std::string&) {
    w_.put<uint64_t>(v.size());
    for (const auto& s : v) w_.put_string(s);
  }
  void operator()(const Vec3& v, const std::string&) {
    for (int i = 0; i < 3; ++i) w_.put(v[i]);
  }
  void operator()(const Mat3& m, const std::string&) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) w_.put(m(i, j));
  }
  void operator()(const Points& m, const std::string&) { matrix(m); }
  void operator()(const Tris& m, const std::string&) { matrix(m); }
  void operator()(const Tets& m, const std::string&) { matrix(m); }
  template <class T>
  void items(const std::vector<T>& v, const std::string&) { w_.put<uint64_t>(v.size()); }
  void muscle_type(MuscleType t, const std::string&) { w_.put(static_cast<uint8_t>(t)); }

  std::vector<uint8_t>& bytes() { return w_.bytes(); }

 private:
  template <class M>
  void matrix(const M& m) {
    static_assert(M::IsRowMajor, "the format stores matrices row-major");
    w_.put<uint64_t>(m.rows());
    w_.put<uint64_t>(m.cols());
    const auto* p = reinterpret_cast<const uint8_t*>(m.data());
    w_.bytes().insert(w_.bytes().end(), p, p + m.size() * sizeof(typename M::Scalar));
  }
  ByteWriter w_;
};

class PayloadReader {
 public:
  PayloadReader(const uint8_t* data, size_t size, const std::string& path)
      : data_(data), size_(size), path_(path), r_(data, size, path) {}

  template <class T, std::enable_if_t<std::is_arithmetic<T>::value, int> = 0>
  void operator()(T& v, const std::string& what) { v = r_.get<T>(what.c_str()); }
  void operator()(std::array<int32_t, 3>& a, const std::string& what) {
    a = r_.get<std::array<int32_t, 3>>(what.c_str());
  }
  void operator()(std::string& s, const std::string& what) { s = r_.get_string(what.c_str()); }
  template <class T>
  void operator()(std::vector<T>& v, const std::string& what) {
    v = r_.get_vector<T>(what.c_str());
  }
  void operator()(std::vector<std::string>& v, const std::string& what) {
    items(v, what);
    for (auto& s : v) s = r_.get_string(what.c_str());
  }
  void operator()(Vec3& v, const std::string& what) {
    for (int i = 0; i < 3; ++i) v[i] = r_.get<double>(what.c_str());
  }
  void operator()(Mat3& m, const std::string& what) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m(i, j) = r_.get<double>(what.c_str());
  }
  void operator()(Points& m, const std::string& what) { matrix(m, what); }
  void operator()(Tris& m, const std::string& what) { matrix(m, what); }
  void operator()(Tets& m, const std::string& what) { matrix(m, what); }
  template <class T>
  void items(std::vector<T>& v, const std::string& what) {
    const auto n = r_.get<uint64_t>(what.c_str());
    // Every item takes at least 8 bytes, so a corrupt count cannot make us
    // allocate far more than the file holds.
    require(n <= r_.remaining() / 8, path_ + ": truncated while reading " + what);
    v.resize(n);
  }
  void muscle_type(MuscleType& t, const std::string& what) {
    const auto v = r_.get<uint8_t>(what.c_str());
    require(v <= uint8_t(MuscleType::Sphincter),
            path_ + ": " + what + " has unknown value " + std::to_string(v));
    t = MuscleType(v);
  }

  size_t remaining() const { return r_.remaining(); }

 private:
  // ByteReader has no bulk read without a count prefix, and a per-element
  // get() would build an error string per value; copy the block directly and
  // re-seat the reader after it.
  template <class M>
  void matrix(M& m, const std::string& what) {
    using S = typename M::Scalar;
    const auto rows = r_.get<uint64_t>(what.c_str());
    const auto cols = r_.get<uint64_t>(what.c_str());
    require(cols == uint64_t(M::ColsAtCompileTime),
            path_ + ": " + what + " has " + std::to_string(cols) + " columns, expected " +
                std::to_string(M::ColsAtCompileTime));
    const size_t at = size_ - r_.remaining();
    require(rows <= (size_ - at) / (cols * sizeof(S)), path_ + ": truncated while reading " + what);
    m.resize(Eigen::Index(rows), Eigen::Index(cols));
    const size_t n = rows * cols * sizeof(S);
    if (n) std::memcpy(m.data(), data_ + at, n);
    r_ = ByteReader(data_ + at + n, size_ - at - n, path_);
  }

  const uint8_t* data_;
  size_t size_;
  std::string path_;
  ByteReader r_;
};

std::vector<uint8_t> serialize(const Rig& rig) {
  PayloadWriter w;
  visit_rig(w, rig);
  return std::move(w.bytes());
}

// Messages are built only on failure: the checks run per element over meshes
// with millions of entries.
class Validator {
 public:
  explicit Validator(const std::string& context) : ctx_(context) {}

  void check(bool ok, const std::string& field, const std::string& problem) const {
    if (!ok) fail(field, problem);
  }
  void size(const std::string& field, size_t n, size_t expected) const {
    if (n != expected)
      fail(field, "has " + std::to_string(n) + " entries, expected " + std::to_string(expected));
  }
  template <class T>
  void finite(const std::string& field, const T* p, size_t n) const {
    for (size_t i = 0; i < n; ++i)
      if (!std::isfinite(p[i]))
        fail(field, "has a non-finite value at element " + std::to_string(i));
  }
  template <class T>
  void finite(const std::string& field, const std::vector<T>& v) const {
    finite(field, v.data(), v.size());
  }
  void finite(const std::string& field, const Points& m) const {
    for (Eigen::Index r = 0; r < m.rows(); ++r)
      if (!m.row(r).allFinite())
        fail(field, "row " + std::to_string(r) + " has a non-finite value");
  }
  // Every p[i] must lie in [lo, hi).
  template <class T>
  void in_range(const std::string& field, const T* p, size_t n, long lo, long hi) const {
    for (size_t i = 0; i < n; ++i)
      if (long(p[i]) < lo || long(p[i]) >= hi)
        fail(field, "element " + std::to_string(i) + " is " + std::to_string(long(p[i])) +
                        ", outside " + range(lo, hi));
  }
  template <class T>
  void in_range(const std::string& field, const std::vector<T>& v, long lo, long hi) const {
    in_range(field, v.data(), v.size(), lo, hi);
  }
  // Every entry of an index matrix (triangles, tets) must lie in [0, count).
  template <class M>
  void indices(const std::string& field, const M& m, long count) const {
    for (Eigen::Index r = 0; r < m.rows(); ++r)
      for (Eigen::Index c = 0; c < m.cols(); ++c)
        if (m(r, c) < 0 || m(r, c) >= count)
          fail(field, "row " + std::to_string(r) + " references vertex " +
                          std::to_string(m(r, c)) + ", outside " + range(0, count));
  }

 private:
  [[noreturn]] void fail(const std::string& field, const std::string& problem) const {
    throw Error(ctx_ + ": " + field + " " + problem);
  }
  static std::string range(long lo, long hi) {
    return "[" + std::to_string(lo) + ", " + std::to_string(hi) + ")";
  }
  const std::string& ctx_;
};

void validate_sim_mesh(const Validator& v, const SimMesh& s, const std::string& p, size_t nv,
                       size_t muscles) {
  const size_t nodes = size_t(s.mesh.X.rows()), tets = size_t(s.mesh.T.rows());
  v.finite(p + ".mesh.X", s.mesh.X);
  v.indices(p + ".mesh.T", s.mesh.T, long(nodes));
  v.size(p + ".muscle", s.muscle.size(), tets);
  v.in_range(p + ".muscle", s.muscle, -1, long(muscles));
  v.size(p + ".muscle_fraction", s.muscle_fraction.size(), tets);
  v.finite(p + ".muscle_fraction", s.muscle_fraction);
  v.size(p + ".fibre", s.fibre.size(), 3 * tets);
  v.finite(p + ".fibre", s.fibre);
  v.in_range(p + ".dirichlet", s.dirichlet, 0, long(nodes));
  v.size(p + ".dirichlet_bone", s.dirichlet_bone.size(), s.dirichlet.size());
  v.in_range(p + ".dirichlet_bone", s.dirichlet_bone, 0, 2);
  v.size(p + ".surface.tet", s.surface.tet.size(), nv);
  v.in_range(p + ".surface.tet", s.surface.tet, 0, long(tets));
  v.size(p + ".surface.weights", s.surface.weights.size(), 4 * nv);
  v.finite(p + ".surface.weights", s.surface.weights);
  v.size(p + ".surface.outside", s.surface.outside.size(), nv);
  v.in_range(p + ".surface.outside", s.surface.outside, 0, 2);
  v.in_range(p + ".tracks", s.tracks, 0, long(nv));
  v.size(p + ".track_area", s.track_area.size(), s.tracks.size());
  v.finite(p + ".track_area", s.track_area);
}

}  // namespace

void validate_rig(const Rig& rig, const std::string& context) {
  const Validator v(context);
  const size_t nv = size_t(rig.surface.rows());
  const size_t shapes = rig.blendshape_names.size(), muscles = rig.muscles.size();

  v.finite("surface", rig.surface);
  v.indices("surface_tris", rig.surface_tris, long(nv));
  // Synthetic rigs have no source mesh, hence 0 is allowed.
  v.check(rig.surface_source_vertex.empty() || rig.surface_source_vertex.size() == nv,
          "surface_source_vertex", "has " + std::to_string(rig.surface_source_vertex.size()) +
                                       " entries, expected 0 or " + std::to_string(nv));
  v.size("blendshape_deltas", rig.blendshape_deltas.size(), shapes * nv * 3);
  v.finite("blendshape_deltas", rig.blendshape_deltas);
  v.size("landmark_vertex", rig.landmark_vertex.size(), rig.landmark_names.size());
  v.in_range("landmark_vertex", rig.landmark_vertex, 0, long(nv));

  v.finite("jaw.pivot", rig.jaw.pivot.data(), 3);
  v.finite("jaw.axis", rig.jaw.axis.data(), 3);
  v.finite("jaw.open_angle_deg", &rig.jaw.open_angle_deg, 1);
  v.finite("jaw.hinge_max_error_cm", &rig.jaw.hinge_max_error_cm, 1);
  if (rig.teeth_lower.V.rows() > 0 && rig.jaw.pivot.allFinite()) {
    const Vec3 c = rig.teeth_lower.V.colwise().mean().transpose();
    const double d = (rig.jaw.pivot - c).norm();
    v.check(d <= kJawPivotMaxCm, "jaw.pivot",
            "lies " + number_text(d, 3) + " cm from the lower teeth (a degenerate hinge fit of an older facesr: "
            "jaw shapes other than jawOpen would move the jaw that far); rebuild the rig");
  }
  for (const auto& s : rig.jaw.shapes) {
    const std::string p = "jaw shape '" + s.name + "'";
    v.finite(p + " R", s.R.data(), 9);
    v.finite(p + " t", s.t.data(), 3);
    v.finite(p + " fit_rms_cm", &s.fit_rms_cm, 1);
  }

  for (const auto& m : rig.muscles) {
    const std::string p = "muscle '" + m.name + "'";
    v.check(m.type == MuscleType::Line || m.type == MuscleType::Sphincter, p,
            "has unknown type " + std::to_string(int(m.type)));
    v.finite(p + " curve", m.curve);
    v.finite(p + " radius", &m.radius, 1);
  }
  v.size("activation", rig.activation.size(), shapes * muscles);
  v.finite("activation", rig.activation);

  v.finite("teeth_upper.V", rig.teeth_upper.V);
  v.indices("teeth_upper.F", rig.teeth_upper.F, long(rig.teeth_upper.V.rows()));
  v.finite("teeth_lower.V", rig.teeth_lower.V);
  v.indices("teeth_lower.F", rig.teeth_lower.F, long(rig.teeth_lower.V.rows()));

  validate_sim_mesh(v, rig.hr, "hr", nv, muscles);
  validate_sim_mesh(v, rig.lr, "lr", nv, muscles);

  v.finite("lattice.origin", rig.lattice.origin.data(), 3);
  v.finite("lattice.cell", &rig.lattice.cell, 1);
  v.in_range("lattice.dims", rig.lattice.dims.data(), 3, 0, 1l << 31);

  const auto& pd = rig.predeform;
  v.finite("predeform.angle_deg", &pd.angle_deg, 1);
  v.check(pd.surface_jaw_weight.empty() || pd.surface_jaw_weight.size() == nv,
          "predeform.surface_jaw_weight", "has " + std::to_string(pd.surface_jaw_weight.size()) +
                                              " entries, expected 0 or " + std::to_string(nv));
  v.finite("predeform.surface_jaw_weight", pd.surface_jaw_weight);
  v.check(pd.surface_predeformed.rows() == 0 || size_t(pd.surface_predeformed.rows()) == nv,
          "predeform.surface_predeformed",
          "has " + std::to_string(pd.surface_predeformed.rows()) + " rows, expected 0 or " +
              std::to_string(nv));
  v.finite("predeform.surface_predeformed", pd.surface_predeformed);

  v.finite("build_seconds", &rig.build_seconds, 1);
}

uint64_t rig_checksum(const Rig& rig) {
  // The build record (build_seconds, source: the last two payload fields, an
  // f64 and a string) is left out, so rebuilding a head with the same code
  // gives the same identity and a shipped model still fits.
  const auto payload = serialize(rig);
  const size_t record = sizeof(double) + sizeof(uint64_t) + rig.source.size();
  return fnv1a64(payload.data(), payload.size() - record);
}

void save_rig(const Rig& rig, const std::string& path) {
  validate_rig(rig, path);
  const auto payload = serialize(rig);
  ByteWriter file;
  file.put(kMagic);
  file.put<uint32_t>(kVersion);
  file.put<uint32_t>(0);  // flags
  file.put<uint64_t>(payload.size());
  file.bytes().insert(file.bytes().end(), payload.begin(), payload.end());
  file.put<uint64_t>(fnv1a64(payload.data(), payload.size()));
  const auto& bytes = file.bytes();
  write_file_atomically(path, [&](std::ostream& out) {
    out.write(reinterpret_cast<const char*>(bytes.data()), std::streamsize(bytes.size()));
  });
}

Rig load_rig(const std::string& path) {
  const auto bytes = read_file_bytes(path);
  ByteReader header(bytes.data(), bytes.size(), path);
  require(header.get<std::array<char, 8>>("magic") == kMagic,
          path + ": not a facesr rig file (bad magic)");
  const auto version = header.get<uint32_t>("format version");
  require(version == kVersion, path + ": rig format version " + std::to_string(version) +
                                   " is not supported (expected " + std::to_string(kVersion) + ")");
  const auto flags = header.get<uint32_t>("flags");
  require(flags == 0, path + ": unknown rig flags " + std::to_string(flags));
  const auto payload_size = header.get<uint64_t>("payload size");
  const size_t after_header = header.remaining();
  require(payload_size <= after_header && after_header - payload_size >= kChecksumBytes,
          path + ": truncated (header announces " + std::to_string(payload_size) +
              " payload bytes plus an 8-byte checksum, but only " +
              std::to_string(after_header) + " bytes follow the header)");
  const size_t trailing = after_header - payload_size - kChecksumBytes;
  require(trailing == 0,
          path + ": " + std::to_string(trailing) + " unexpected bytes after the checksum");

  const uint8_t* payload = bytes.data() + kHeaderBytes;
  uint64_t stored;
  std::memcpy(&stored, payload + payload_size, sizeof stored);
  require(fnv1a64(payload, payload_size) == stored,
          path + ": checksum mismatch, the file is corrupt");

  Rig rig;
  PayloadReader reader(payload, payload_size, path);
  visit_rig(reader, rig);
  require(reader.remaining() == 0, path + ": " + std::to_string(reader.remaining()) +
                                       " unexpected bytes at the end of the payload");
  validate_rig(rig, path);
  return rig;
}

}  // namespace facesr
