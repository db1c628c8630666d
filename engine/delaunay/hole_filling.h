// Filling the hole a removed vertex leaves (Triangulation::remove): the pentatopes that replace
// its star, as a small list the removal then commits.
//
// The fill is the Delaunay triangulation of the star's link restricted to the hole. wrap_hole()
// builds it by gift-wrapping from the hole's boundary: for each open facet, the link vertex whose
// sphere through the facet reaches least far into the open side (a floating-point ranking, ties
// decided by the exact in-sphere test). Building the link's whole triangulation point by point
// took four fifths of a removal (28 points, ~500 pentatopes made and mostly thrown away, for the
// ~90 that fill the hole). The result is accepted only once it is proven: every pentatope
// positively oriented, every facet shared by exactly two, and the exact in-sphere test (with the
// triangulation's symbolic tie-break) passing across every facet, the hole's boundary included.
// A locally Delaunay filling of the hole is the Delaunay one, so the result is the same as the
// link triangulation's; when a check fails the caller builds that instead.
#pragma once

#include <cstdint>
#include <vector>

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {

/// A facet of the hole's boundary: the star pentatope it belongs to and the pentatope beyond it.
struct HoleFacet {
  CellId star_cell;
  int slot;          // the removed vertex's index in star_cell: the facet is opposite it
  CellId outside;    // the pentatope beyond the facet
  int outside_slot;  // the index of star_cell among outside's neighbors
};

/// A pentatope of the fill: vertices positively oriented; n[i] >= 0 is the fill pentatope across
/// facet i, n[i] < 0 the hole facet ~n[i].
struct FillCell {
  VertexId v[5];
  std::int32_t n[5];
};

/// Gift-wraps the hole (its boundary facets `hole`, the removed vertex's link vertices `link`) into
/// `fill`; false when the result cannot be proven Delaunay (the caller then fills the hole
/// another way).
bool wrap_hole(const PentatopeStore& store, const std::vector<HoleFacet>& hole,
               const std::vector<VertexId>& link, std::vector<FillCell>& fill);

/// All holes filled and those wrap_hole() could not prove, left to the link triangulation (per
/// thread, since its start): tests check that the fallback is rare. Tests also turn wrapping
/// off to compare the two ways.
struct HoleCounters {
  std::uint64_t holes = 0;
  std::uint64_t fallbacks = 0;
  bool wrap = true;
};
HoleCounters& hole_counters();

/// The facets of `fill` matched to each other and to the hole: n[] of every fill pentatope set
/// from the facets' vertex ids. False when a facet matches none or more than one.
bool link_fill(const PentatopeStore& store, const std::vector<HoleFacet>& hole,
               std::vector<FillCell>& fill);

}  // namespace mesh4d::delaunay
