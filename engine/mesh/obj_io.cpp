#include "mesh/obj_io.h"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <sstream>

#include "core/atomic_file.h"
#include "core/binary_io.h"
#include "core/error.h"

namespace facesr {
namespace {

struct ObjParse {
  std::vector<double> v;
  std::vector<int32_t> f;
};

ObjParse parse(const std::string& path, bool faces) {
  const auto bytes = read_file_bytes(path);
  std::string text(bytes.begin(), bytes.end());
  ObjParse out;
  size_t pos = 0;
  long line_no = 0;
  std::vector<long> poly;
  while (pos < text.size()) {
    size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    ++line_no;
    const char* s = text.c_str() + pos;
    const char* e = text.c_str() + end;
    if (end < text.size()) text[end] = '\0';  // number parsing must not run past the line
    pos = end + 1;
    while (s < e && (*s == ' ' || *s == '\t')) ++s;
    auto where = [&] { return path + ":" + std::to_string(line_no) + ": "; };
    if (s + 1 < e && s[0] == 'v' && (s[1] == ' ' || s[1] == '\t')) {
      const char* p = s + 2;
      for (int k = 0; k < 3; ++k) {
        char* q = nullptr;
        const double x = std::strtod(p, &q);
        require(q != p, where() + "malformed vertex row (expected 3 numbers)");
        require(std::isfinite(x), where() + "vertex coordinate is NaN or infinite");
        out.v.push_back(x);
        p = q;
      }
    } else if (faces && s + 1 < e && s[0] == 'f' && (s[1] == ' ' || s[1] == '\t')) {
      poly.clear();
      const char* p = s + 2;
      while (true) {
        while (p < e && (*p == ' ' || *p == '\t' || *p == '\r')) ++p;
        if (p >= e || *p == '\0') break;
        char* q = nullptr;
        const long idx = std::strtol(p, &q, 10);
        require(q != p, where() + "malformed face row");
        const long nv = long(out.v.size() / 3);
        const long i0 = idx > 0 ? idx - 1 : nv + idx;
        require(idx != 0 && i0 >= 0 && i0 < nv, where() + "face index " + std::to_string(idx) +
                                                    " out of range (" + std::to_string(nv) + " vertices so far)");
        poly.push_back(i0);
        p = q;
        while (p < e && *p != ' ' && *p != '\t' && *p != '\0') ++p;  // skip /vt/vn
      }
      require(poly.size() >= 3, where() + "face with fewer than 3 vertices");
      for (size_t k = 1; k + 1 < poly.size(); ++k) {
        out.f.push_back(int32_t(poly[0]));
        out.f.push_back(int32_t(poly[k]));
        out.f.push_back(int32_t(poly[k + 1]));
      }
    }
  }
  require(!out.v.empty(), path + ": no vertices found (not an OBJ file?)");
  return out;
}

}  // namespace

TriMesh read_obj(const std::string& path) {
  auto p = parse(path, true);
  TriMesh m;
  m.V = Eigen::Map<Points>(p.v.data(), long(p.v.size() / 3), 3);
  m.F = Eigen::Map<Tris>(p.f.data(), long(p.f.size() / 3), 3);
  return m;
}

Points read_obj_vertices(const std::string& path) {
  auto p = parse(path, false);
  return Eigen::Map<Points>(p.v.data(), long(p.v.size() / 3), 3);
}

void write_obj(const std::string& path, const Points& V, const Tris& F) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "# facesr mesh, units: cm\n";
    char buf[128];
    for (int i = 0; i < V.rows(); ++i) {
      std::snprintf(buf, sizeof buf, "v %.9g %.9g %.9g\n", V(i, 0), V(i, 1), V(i, 2));
      out << buf;
    }
    for (int f = 0; f < F.rows(); ++f)
      out << "f " << F(f, 0) + 1 << ' ' << F(f, 1) + 1 << ' ' << F(f, 2) + 1 << '\n';
  });
}

}  // namespace facesr
