// What a mesh in periodic time (Mesh4::period) is made of, for the checks and cuts that need the
// glued cycle: its vertices glued at the seam, and the mesh unrolled over a period and more.
#pragma once

#include <cstdint>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

/// Each vertex's id in the glued mesh: the earlier twin for a vertex past the period
/// (Mesh4::periodic_twins), else its own. The identity for open time.
std::vector<std::uint32_t> glued_vertex_ids(const Mesh4& mesh);

/// The same pentatopes, boundary tetrahedra and vertices, with vertex ids glued: the cycle's
/// combinatorics (positions past the period stay where they are, so geometry is not its own).
/// Open time: a copy.
Mesh4 glued(const Mesh4& mesh);

/// An open mesh of the cycle that any instant of [period_start, period_start + period) cuts
/// wholly: the pentatopes, then each again one period earlier (vertices past the period are their
/// earlier twins there, and the others get copies), so that a section meets every pentatope's
/// class once. Pentatope p + size() is the copy of p. Open time: a copy.
Mesh4 unrolled(const Mesh4& mesh);

/// t moved by whole periods into [period_start, period_start + period) (unchanged in open time).
double wrapped_time(const Mesh4& mesh, double t);

}  // namespace mesh4d::mesh
