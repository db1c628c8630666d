// Validity of a triangulation, checked exhaustively (tests call it after every operation on small
// cases): combinatorics, orientation, and the Delaunay property with the exact predicates.
#pragma once

#include <string>

#include "delaunay/triangulation.h"

namespace mesh4d::delaunay {

struct CheckResult {
  bool ok = true;
  std::string error;  // the first violation found, with the ids involved
};

/// Checks that:
///  - every live pentatope has five distinct valid vertices and five live neighbors;
///  - neighbors are mutual and share exactly the facet opposite the slot;
///  - finite pentatopes have orient4 > 0; infinite ones see their finite neighbor's far vertex
///    on the inner side of their hull facet;
///  - across every facet, the far vertex of the neighbor is not in conflict with the pentatope
///    (local Delaunay, with the symbolic tie-break), which implies global Delaunay;
///  - every vertex in the triangulation has a live incident pentatope that contains it, and the
///    vertex count matches.
CheckResult check_triangulation(const Triangulation& t);

}  // namespace mesh4d::delaunay
