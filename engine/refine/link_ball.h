// Balls in a vertex's link (docs/refinement.md, "Closed, manifold region boundaries where labels
// meet"). The star of an interior vertex v, less v, is a triangulated 3-sphere; a region's
// boundary is a 2-sphere at v exactly when the region's part of that sphere (or the rest) is a
// 3-ball. Where neither tier of single moves mends a link, the manifold step proposes the
// nearest ball: grown tetrahedron by tetrahedron from a seed inside the region's part (or the
// rest's), each added only where it meets the ball in a disk, so the result is a ball by
// construction. What the ball leaves out changes label.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "delaunay/pentatope_store.h"

namespace mesh4d::refine {

/// The largest ball grown from star[seed] through the pentatopes with allowed[k] (k: their place
/// in `star`, v's star), added in breadth-first order until none more can be: in[k] per
/// pentatope.
std::vector<char> grow_link_ball(const delaunay::PentatopeStore& store, mesh4d::VertexId v,
                                 std::span<const delaunay::CellId> star,
                                 const std::vector<char>& allowed, std::size_t seed);

}  // namespace mesh4d::refine
