// The labels of the pentatopes around a triangle, read as a cycle (relabeling.cpp): a
// label's region is pinched at the triangle when it occupies two or more separate arcs of it.
// Pure functions on label sequences, so that the relabeling's choices can be tested alone.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::refine {

/// A maximal run of consecutive positions of the cycle (it may wrap past the end).
struct Arc {
  std::size_t begin;
  std::size_t length;
};

/// The arcs whose labels are l (of_l) or are not l (!of_l). A cycle entirely of that kind is
/// one arc from 0.
std::vector<Arc> label_arcs(const std::vector<domain::Label>& labels, domain::Label l, bool of_l);

/// How many labels other than the background (0) occupy two or more arcs.
int split_labels(const std::vector<domain::Label>& labels);

/// A relabeling of some positions: (position, new label).
using LinkMoves = std::vector<std::pair<std::size_t, domain::Label>>;

/// The ways to join label l's arcs into one: fill every gap but one with l; or give every arc
/// of l but one the label just before it; or just after it. Three options for each run kept,
/// the longest gap and arc first (their options need the fewest moves), then the others in
/// cycle order. Empty when l has fewer than two arcs.
std::vector<LinkMoves> joining_moves(const std::vector<domain::Label>& labels, domain::Label l);

}  // namespace mesh4d::refine
