// Manifold regions (docs/algorithm.md, "Where labels meet"): where a region's boundary is still
// not a closed 3-manifold at a vertex after the pinch repair and relabeling (manifold_scan.h),
// pentatopes of that vertex's star move to a neighbor's label while that lowers the number of
// failing (vertex, label) pairs around them: each pentatope alone, then facet-adjacent pairs,
// then each piece of the label (or of the rest) around the vertex as a whole, then all that a
// ball grown in the vertex's link (link_ball.h) leaves out. Where a move mends the vertex but
// breaks as many links nearby, the links it broke are repaired in turn, and the whole is kept
// only when the count falls (a detour, one level deep). This decides,
// once, whether two parts that touch at a vertex or edge join or separate. The moves obey
// relabeling.h's rules (all five vertices on ∂Ω; a pentatope entering the output meets the
// quality bounds), every facet a move puts on a boundary has its centroid within Δ/2 of ∂Ω, no
// move pinches more triangles, and the triangulation does not change.
//
// Sampling the restricted facets through failing vertices first, before any move, made new
// failures near three-label junctions faster than it removed them (on the ventricle, 340 failing
// pairs grew to 718 after 1,876 points); after this step, on the few pairs it leaves, it
// converges (manifold_sampling.h).
//
// On one thread the failing pairs are repaired in their order (by vertex, then label). On more,
// each round's pairs are coloured so that no two of a colour can see each other's moves
// (link_repair.h), and one colour's repairs run side by side: the labels depend on the pairs
// alone, not on the number of threads.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <vector>

#include "refine/link_repair.h"
#include "refine/manifold_scan.h"
#include "refine/piece_matching.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

class ManifoldRelabeling {
 public:
  ManifoldRelabeling(RefinementState& state, const PinchScan& scan)
      : state_(state), scan_(scan), repair_(state, scan) {}

  struct Outcome {
    std::size_t moved = 0;                   // pentatopes that changed label
    std::vector<NonManifoldVertex> failing;  // the (vertex, label) pairs left
  };
  /// Over every boundary vertex, or only those `around` (the others' links are known to pass).
  Outcome run(const std::vector<mesh4d::VertexId>* around = nullptr);
  /// After run(): each region's pieces matched with the image's (piece_matching.h): a piece
  /// the image joins to another is removed or bridged, and one the image splits is cut. With
  /// `leave_links`, a cut may leave a few links failing where the mending cannot close them
  /// without joining the pieces again (a vertex both touch): they are listed in the outcome.
  /// Where no cut separates a merged piece, the outcome has surface samples to insert there.
  PieceMatching match_image_pieces(bool leave_links = false);

 private:
  using Move = LabelMove;
  static constexpr long kNotAllowed = LinkRepair::kNotAllowed;
  // One round's repairs of `due`: in order on one thread, side by side in colours on more; the
  // moved pentatopes' vertices are appended to `touched`. Returns how many moved.
  std::size_t repair_all(const std::vector<NonManifoldVertex>& due,
                         std::vector<mesh4d::VertexId>& touched);
  // Whether a walk through `label`'s pentatopes from `from` meets one where `goal` holds (or
  // walks too far to tell); piece_matching.cpp.
  bool reaches(const std::vector<delaunay::CellId>& from, domain::Label label,
               const std::function<bool(delaunay::CellId)>& goal) const;
  // Where ∂Ω crosses the Voronoi edges between `island`'s pentatopes (which stand for image
  // piece `piece`) and their neighbors of the region that stand for another, appended to `out`;
  // piece_matching.cpp.
  void contact_samples(const std::vector<delaunay::CellId>& island, std::uint32_t piece,
                       const std::vector<std::uint32_t>& image_piece,
                       std::vector<RepairPoint>& out) const;
  // Applies `moves` when they may move, pinch nothing more and keep the new boundary near ∂Ω.
  // Links they break are mended by run() around them; they are undone (with the mending)
  // unless no more links fail than before and `done` holds after them.
  // With `guarded`, the mending may not give a pentatope `label` where `done` then fails.
  // `spare`: how many more links may fail after the mending than before (those left go to
  // out.failing).
  bool apply_mended(const std::vector<Move>& moves, const std::function<bool()>& done,
                    PieceMatching& out, bool guarded = false, domain::Label label = 0,
                    std::size_t spare = 0);
  RefinementState& state_;
  const PinchScan& scan_;
  LinkRepair repair_;                   // in order, and for piece matching
  std::vector<LinkRepair> repairers_;   // one per thread, side by side
  std::vector<std::uint64_t> colours_;  // per vertex: the colours whose claims hold it
};

}  // namespace mesh4d::refine
