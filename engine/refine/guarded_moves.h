// Vertex moves that keep the mesh's quality (docs/algorithm.md, "Facet sag"): each vertex moves
// by its offset, and a move that would flip a pentatope (exact orient4), make a sliver that was
// not one, or raise a radius-edge ratio past the bound is halved, at most four times, and then
// dropped. The facet sag's offset and the time caps' flattening both move vertices this way.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "mesh/mesh4.h"
#include "refine/refine_params.h"

namespace mesh4d::refine {

struct GuardedMoves {
  /// By vertex (as `glued` names it): the share of its offset it moved, 1 whole, 0 none.
  std::vector<double> scale;
};

/// Places mesh.vertices[v] at before[v] + scale · offset[glued[v]] for the vertices of `moving`
/// (their own glued ids: a periodic twin pair moves alike), scaled down as above. Only the
/// pentatopes for which `counts` holds are guarded (null: all). Runs on up to
/// working_threads(params) threads.
GuardedMoves move_guarded(mesh::Mesh4& mesh, const std::vector<Point4>& before,
                          const std::vector<std::uint32_t>& glued,
                          const std::vector<Point4>& offset,
                          const std::vector<std::uint32_t>& moving,
                          const std::function<bool(std::uint32_t pentatope)>& counts,
                          const RefineParams& params);

}  // namespace mesh4d::refine
