#pragma once
#include "eval/interior_edges.h"

// DAME, the dihedral angle mesh error of Váša and Rus (2012), as the thesis
// uses it (§3.3.10 and §4.7.1; the thesis states the metric in words and gives
// no equation of its own): for meshes of the same connectivity,
//
//   DAME = sum_e w_e m_e |theta_e - theta'_e| / sum_e w_e      (radians)
//
// over the interior edges e, where
//   theta_e, theta'_e   oriented dihedral angles of e on the reference and the
//                       test mesh (dihedral_angles.h); their difference is
//                       wrapped into [0, pi] so that a fold through +-pi is
//                       not counted as a 2 pi change;
//   w_e                 the visibility weight, which depends on a camera and a
//                       resolution, replaced (as the thesis does, following
//                       Váša and Rus) by triangle area: the area of the two
//                       triangles of e, averaged over the two meshes so that
//                       the metric is symmetric;
//   m_e                 the masking effect: a change of angle is less visible
//                       where the surface is already sharply bent. Modelled as
//                       m_e = 1 / (1 + max(|theta_e|, |theta'_e|) / masking_rad),
//                       so an edge bent by masking_rad counts half. The
//                       thesis names the masking term but not its form; this
//                       form and its constant are our choice (masking_rad = 0
//                       turns masking off).
// Border edges are skipped (no oriented angle exists there, as the thesis
// notes), as are non-manifold and inconsistently oriented edges.
// DAME is 0 for identical meshes and invariant under any rigid motion of
// either mesh (angles and areas are).
namespace facesr {

struct DameOptions {
  // Bend (radians) at which an edge's error counts half. 0.2 rad (11.5 deg):
  // on the face surfaces here (edges of 2-5 mm) smooth skin bends by a few
  // degrees per edge and only creases (lids, lips, nostrils) reach this.
  double masking_rad = 0.2;
};

// reference and test: positions (cm) over the same triangles, from which
// `edges` was computed. Returns 0 when there is no interior edge or no area.
// Throws Error when the two meshes differ in vertex count or an edge refers
// to a vertex outside them.
double dame(const Points& reference, const Points& test, const InteriorEdges& edges, const DameOptions& opt = {});

// Convenience: computes the interior edges of F first.
double dame(const Points& reference, const Points& test, const Tris& F, const DameOptions& opt = {});

}  // namespace facesr
