#include "mesh/tetrahedralize.h"

#include <cstdio>
#include <algorithm>
#include <cstdlib>
#include <sstream>

#include <tetgen.h>

#include "core/error.h"
#include "mesh/remesh.h"

namespace facesr {
namespace {
std::string tetgen_error(int code) {
  switch (code) {
    case 1: return "out of memory";
    case 2: return "internal error";
    case 3: return "the input surface self-intersects";
    case 4: return "a very small input feature (edge or angle) was found";
    case 5: return "two input facets are nearly coplanar and very close";
    case 10: return "the input is invalid";
    default: return "error code " + std::to_string(code);
  }
}
}  // namespace

TetMesh tetrahedralize(const TriMesh& b, const std::vector<Vec3>& holes, const TetgenOptions& opt) {
  require(b.V.rows() >= 4 && b.F.rows() >= 4, "tetrahedralize: boundary surface is empty");
  // TetGen's library build aborts the process (instead of throwing) on some
  // intersecting inputs, so reject them here with a clear message.
  const SurfaceCheck chk = check_surface(b);
  require(chk.closed, "tetrahedralize: the boundary surface is not closed");
  require(!chk.self_intersects, "tetrahedralize: the boundary surface intersects itself (skin and bone surfaces "
                                "overlap or fold); try a finer --flesh-grid");
  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = int(b.V.rows());
  in.pointlist = new REAL[3 * in.numberofpoints];
  for (int i = 0; i < b.V.rows(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = b.V(i, k);
  in.numberoffacets = int(b.F.rows());
  in.facetlist = new tetgenio::facet[in.numberoffacets];
  for (int f = 0; f < b.F.rows(); ++f) {
    tetgenio::facet& fc = in.facetlist[f];
    tetgenio::init(&fc);
    fc.numberofpolygons = 1;
    fc.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&fc.polygonlist[0]);
    fc.polygonlist[0].numberofvertices = 3;
    fc.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) fc.polygonlist[0].vertexlist[k] = b.F(f, k);
  }
  in.numberofholes = int(holes.size());
  if (!holes.empty()) {
    in.holelist = new REAL[3 * holes.size()];
    for (size_t h = 0; h < holes.size(); ++h)
      for (int k = 0; k < 3; ++k) in.holelist[3 * h + k] = holes[h][k];
  }
  std::ostringstream sw;
  // FACESR_TETGEN_VERBOSE=1 shows TetGen's own log when a mesh fails.
  sw << "pz" << (std::getenv("FACESR_TETGEN_VERBOSE") ? "V" : "Q") << "q" << opt.radius_edge << "/" << opt.min_dihedral;
  if (opt.max_volume > 0) sw << "a" << opt.max_volume;
  if (opt.preserve_boundary) sw << "Y";
  long steiner_cap = 0;
  if (opt.max_steiner_per_input > 0) {
    steiner_cap = std::max(10000L, long(opt.max_steiner_per_input * double(in.numberofpoints)));
    sw << "S" << steiner_cap;
  }
  std::string switches = sw.str();
  try {
    ::tetrahedralize(const_cast<char*>(switches.c_str()), &in, &out);
  } catch (int code) {
    throw Error("TetGen failed: " + tetgen_error(code));
  }
  require(out.numberoftetrahedra > 0, "TetGen produced no tetrahedra (is the surface closed?)");
  const long added = long(out.numberofpoints) - long(in.numberofpoints);
  if (steiner_cap > 0 && added >= steiner_cap)
    throw Error("TetGen quality refinement did not converge: it reached its bound of " + std::to_string(steiner_cap) +
                " added points (" + std::to_string(in.numberofpoints) +
                " input points); the boundary surface has slivers or features too small for the quality bound");
  TetMesh m;
  m.X.resize(out.numberofpoints, 3);
  for (int i = 0; i < out.numberofpoints; ++i)
    for (int k = 0; k < 3; ++k) m.X(i, k) = out.pointlist[3 * i + k];
  m.T.resize(out.numberoftetrahedra, 4);
  for (int t = 0; t < out.numberoftetrahedra; ++t) {
    for (int k = 0; k < 4; ++k) m.T(t, k) = out.tetrahedronlist[t * out.numberofcorners + k];
    if (tet_signed_volume(m.X.row(m.T(t, 0)), m.X.row(m.T(t, 1)), m.X.row(m.T(t, 2)),
                          m.X.row(m.T(t, 3))) < 0)
      std::swap(m.T(t, 1), m.T(t, 2));
  }
  return m;
}

}  // namespace facesr
