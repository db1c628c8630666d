// The boundary's sag, offset (docs/algorithm.md, "Facet sag"). A restricted facet is a chord of
// ∂Ω: its vertices lie on ∂Ω and the facet itself on the concave side of the surface, at its
// surface ball's center (where its dual Voronoi edge meets ∂Ω) by the facet's sag. So every
// convex part of a region loses volume, about the sag times its area: on the patients at δ 5 the
// sections lost 1–4 % of the voxels per frame, a thin systolic cavity 9 %. Refining at Δ alone
// does not bound the sag; finer sampling where it is large cost 4–12× the pentatopes.
// Instead each boundary vertex between two labels moves along the boundary's normal by the mean
// depth of ∂Ω below its facets: for a paraboloid under an inscribed regular n-simplex that is
// (1 − 1/(n+2)) times the depth at the facet's circumcenter, 4/5 for the tetrahedra here.
// Vertices then lie off ∂Ω by 4/5 of their facets' mean sag (on the patients at δ 5, at most
// up to about a voxel), and volumes are kept. The mesh's combinatorics, labels and pieces
// do not change; a move that would flip a pentatope, make it a sliver or raise its radius-edge
// ratio past the bound is halved, and after four halvings dropped. What a facet's vertices did not
// move (held back, or a junction's share) its vertices that moved whole take over, up to their own
// depth again, in one more guarded move.
#pragma once

#include <cstddef>

#include "domain/surface_oracle.h"
#include "mesh/mesh4.h"
#include "refine/frame_volume_fit.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

struct SagOffset {
  std::size_t facets = 0;  // restricted facets whose sag was measured
  std::size_t moved = 0;   // vertices offset (a periodic twin pair counts once)
  std::size_t held = 0;    // moves cut short or dropped for a pentatope's quality
  // The volume the facets' held moves and junction vertices left, and how much of it their
  // vertices that moved whole took over (4-volume, physical units).
  double held_volume = 0, spread_volume = 0;
  double mean_sag = 0;        // of the facets, |sag| weighted by area, physical units
  double largest_offset = 0;  // of any vertex
  FrameVolumeFit fit;         // the frames' volumes fitted after the offset
  double seconds = 0;         // the whole step, wall clock
};

/// Offsets the boundary vertices of `mesh` that lie on one interface only (junctions and the
/// vertices of more than two labels stay), on up to working_threads(params) threads. The
/// oracle is the one the mesh was refined against. In periodic time a vertex and its twin move
/// alike. Then, with RefineParams::fit_frame_volumes, the same vertices fit the sections at the
/// frames to the voxels (frame_volume_fit.h).
SagOffset offset_facet_sag(mesh::Mesh4& mesh, const domain::SurfaceOracle& oracle,
                           const RefineParams& params);

}  // namespace mesh4d::refine
