// Relabeling an output pentatope without changing any region's topology. A pentatope σ may move
// from label B to label A when
// - σ shares a facet with each of the two;
// - every face of σ that another pentatope of A holds lies in a facet σ shares with A, so that A
//   gains a 4-ball glued along a 3-ball of its boundary;
// - every face of σ that anything but B holds (another pentatope of A or of a third label, or
//   the outside) lies in a facet σ does not share with B, so that the part of σ on B's boundary
//   is a 3-ball and B gives up a 4-ball as a shelling step does.
// (A union of k < 5 facets of σ is a 3-ball.) Neither region's pieces nor the links of its
// boundary's simplices change, and the other labels' regions do not change at all: σ is
// "simple", as a simple point is in digital topology. Without the third condition's other
// labels and outside, B's boundary could pinch at a triangle of σ where the cycle of
// pentatopes around it leaves B twice.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>

#include "mesh/mesh4.h"

namespace mesh4d::refine {

/// Asks `target` for each pentatope the label it should take (its own or 0: none), and moves it
/// there where that is simple as above; a move can make a neighbor's simple, so the refused are
/// asked again after each pass that moved some. The boundary tetrahedra are made again where
/// labels changed (in the order extraction gives them). In periodic time the pentatopes across
/// the seam are neighbors. Returns how many pentatopes moved.
std::size_t relabel_simple(mesh::Mesh4& mesh,
                           const std::function<mesh::Label(std::uint32_t pentatope)>& target);

}  // namespace mesh4d::refine
