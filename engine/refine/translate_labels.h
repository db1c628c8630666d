// Periodic time's invariant that the glued mesh rests on (docs/algorithm.md, "Periodic time"):
// a pentatope's translates in the other sheets of the covering carry its label. The extraction
// outputs the middle sheet's pentatopes and reads the labels of their neighbors across the seam
// from the sheet below, and the scans count triangles whose pentatopes lie in two sheets: a
// translate with another label is a boundary facet at the seam that the glued mesh does not
// have, or a pinch that it has but nothing counts.
#pragma once

#include <cstddef>
#include <string>

#include "refine/refinement_state.h"

namespace mesh4d::refine {

struct TranslateLabels {
  std::size_t representatives = 0;  // live finite representatives, each with its translates
  std::size_t translates = 0;       // their translates found in the other sheets
  std::size_t mismatched = 0;       // of the translates, those with another output label
  std::string first;                // the first mismatch, in words (empty: none)
};

/// Compares every representative's output label with its translates' (none in open time).
TranslateLabels compare_translate_labels(const RefinementState& state);

}  // namespace mesh4d::refine
