// What ManifoldRelabeling::match_image_pieces() (piece_matching.cpp) did: each region's
// facet-connected pieces matched with its label's pieces in the image, as the label function
// joins them (SurfaceOracle::pieces, domain/label_pieces.h). A pentatope stands for the image
// piece its circumcenter's voxel belongs to (when that voxel has the pentatope's label). Where
// a region thins below Δ the refinement can get the match wrong two ways, and this step mends
// each by moving a few pentatopes to another label (docs/refinement.md, step 6):
// - split: two pieces of the region stand for one image piece. The smaller takes its
//   neighbors' label (up to 64 pentatopes: the cut-off pieces seen on the patients), or else a
//   bridge of up to eight pentatopes between the two, through other labels, takes the region's
//   label;
// - merged: one piece stands for two image pieces that meet only diagonally, near a voxel
//   corner the label function gives to another label. The layer of pentatopes where the two
//   meet, up to three deep, takes its neighbors' label.
// Every move obeys the manifold step's rules: allowed pentatopes only and no new boundary facet
// more than Δ/2 from ∂Ω. Where no cut separates a merged piece (the rules joined the two across
// the corner again, or every cut breaks links), ∂Ω is too coarsely sampled there: the points
// where the Voronoi edges between the two leave the label are handed back, for the refiner to
// insert before it matches again. Links that moves break are mended by the manifold step around
// them (which may not join a cut piece again), and the moves are undone unless no more links fail
// than before (a few more may be left to the manifold sampling, on request). A label's largest
// piece never goes.
#pragma once

#include <cstddef>
#include <vector>

#include "refine/manifold_scan.h"
#include "refine/operation.h"

namespace mesh4d::refine {

struct PieceMatching {
  std::size_t extra_found = 0;   // pieces that stand for an image piece a larger one stands for
  std::size_t removed = 0;       // of those, given their neighbors' label
  std::size_t bridged = 0;       // of those, joined to the larger one
  std::size_t merged_found = 0;  // image pieces a piece stands for beside its main one
  std::size_t cut = 0;           // of those, cut off
  std::size_t moved = 0;         // pentatopes that changed label
  std::size_t links_mended = 0;  // failing (vertex, label) links the moves mended
  // Every failing link the kept moves left, for the manifold sampling (with `leave_links`,
  // manifold_relabeling.h, a cut may leave a few more than failed before it).
  std::vector<NonManifoldVertex> failing;
  // Of the merged pieces no cut separated: where ∂Ω crosses the Voronoi edges between the
  // pentatopes that stand for the two image pieces (dual to the facets where they meet).
  std::vector<RepairPoint> unseparated;
};

}  // namespace mesh4d::refine
