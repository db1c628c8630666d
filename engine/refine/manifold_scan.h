// Where a region's boundary is not a closed 3-manifold at a vertex (docs/algorithm.md, "Where
// labels meet"): the boundary tetrahedra of label L through boundary vertex v, less v, are
// triangles that must form a 2-sphere (mesh/link_topology.h). Two parts of L that meet only at v
// (or at an edge or triangle through it), a pinched triangle, or L wrapping around v all break
// it. The certificate makes the same test on the output; the refiner makes it here, on the
// triangulation, to repair where it fails.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "refine/refinement_state.h"

namespace mesh4d::refine {

struct NonManifoldVertex {
  mesh4d::VertexId vertex;
  domain::Label label;
};

/// l's boundary triangles in the link of v, each sorted; how many pentatopes of the star have l
/// goes to *inside.
void region_link(const RefinementState& state, mesh4d::VertexId v,
                 std::span<const delaunay::CellId> star, domain::Label l,
                 std::vector<std::array<std::uint32_t, 3>>& link, std::size_t* inside);

/// Whether label l's region boundary fails to be a 2-sphere's cone at v, whose star (all its
/// pentatopes) is given; false where l has no boundary at v (absent, or filling the star).
bool region_link_fails(const RefinementState& state, mesh4d::VertexId v,
                       std::span<const delaunay::CellId> star, domain::Label l);

/// Where l's failing link at v is not locally a disk: the link vertices w whose triangles do not
/// close into one circle around w (the edge vw is where the region's boundary is not a
/// manifold). Empty when the link is locally a surface everywhere (then it is disconnected or
/// has a handle).
std::vector<mesh4d::VertexId> link_trouble(const RefinementState& state, mesh4d::VertexId v,
                                           std::span<const delaunay::CellId> star, domain::Label l);

/// Every failing (vertex, label), by vertex then label, from a scan of the whole triangulation
/// on up to RefineParams::threads threads.
std::vector<NonManifoldVertex> find_non_manifold_vertices(const RefinementState& state);

/// The failing (vertex, label) pairs at `vertices` (removed ones skipped), in the order given.
std::vector<NonManifoldVertex> failing_pairs_at(const RefinementState& state,
                                                const std::vector<mesh4d::VertexId>& vertices);

/// Sorts `pairs` by vertex then label and keeps each once (in periodic time a vertex and its
/// twin stand for the same pair: counted_vertex).
void distinct_pairs(std::vector<NonManifoldVertex>& pairs);

/// The vertex whose link stands for v's in the output: v itself in open time and in periodic
/// time's middle sheet; elsewhere in the covering its twin in the middle sheet (the same link
/// where the covering is trusted, and none of the cut-off's where it is not), or kNoVertex.
mesh4d::VertexId counted_vertex(const RefinementState& state, mesh4d::VertexId v);

/// The labels failing at counted_vertex(v) (its star is collected into `star`; nothing where
/// there is none).
void non_manifold_labels_at(const RefinementState& state, mesh4d::VertexId v,
                            std::vector<delaunay::CellId>& star,
                            std::vector<NonManifoldVertex>* out);

}  // namespace mesh4d::refine
