// The output mesh from the final triangulation (docs/algorithm.md, "Output"): the finite
// pentatopes whose label is not the background, tagged with it, and the boundary tetrahedra
// between labels, on up to RefineParams::threads threads.
#pragma once

#include <string>
#include <vector>

#include "mesh/mesh4.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {

/// Adds a warning when no pentatope is kept.
mesh::Mesh4 extract(const RefinementState& state, std::vector<std::string>& warnings);

}  // namespace mesh4d::refine
