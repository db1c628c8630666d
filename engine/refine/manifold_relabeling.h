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
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>
#include <vector>

#include "refine/manifold_scan.h"
#include "refine/piece_matching.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

class ManifoldRelabeling {
 public:
  ManifoldRelabeling(RefinementState& state, const PinchScan& scan) : state_(state), scan_(scan) {}

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
  struct Move {
    delaunay::CellId cell;
    domain::Label to;
  };
  // gain_of() of moves of which one may not move.
  static constexpr long kNotAllowed = std::numeric_limits<long>::min();
  // One failing pair: the best moves found around it, applied, and how many failing pairs they
  // mended in all to *gained; false when none helps. depth > 0: a move that mends f but breaks
  // others may be followed by repairs of those, depth - 1 levels down.
  bool repair(const NonManifoldVertex& f, int depth, long* gained);
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
  // Applies `moves`, journaled so that undo_to() can take them back.
  void apply(const std::vector<Move>& moves);
  void undo_to(std::size_t journal_mark, std::size_t touched_mark);
  // The star of u, kept while one failing vertex is repaired (labels change, stars do not).
  const std::vector<delaunay::CellId>& star_of(mesh4d::VertexId u);
  // Failing (vertex, label) pairs over the moved pentatopes' vertices and the labels involved;
  // `current`: with the labels as they are (kept in current_ while f is repaired).
  long failing_over(const std::vector<Move>& moves, const std::vector<domain::Label>& labels,
                    bool current);
  // How many failing pairs `moves` removes; the least long when one of them may not move.
  long gain_of(const std::vector<Move>& moves);
  // Whether `moves` pinch no triangle more and keep their new boundary facets near ∂Ω; with
  // `pinches_mended`, only the latter (a pinched triangle fails its vertices' links, which the
  // caller then requires mended).
  bool acceptable(const std::vector<Move>& moves, bool pinches_mended = false);
  // Whether every facet that `moves` (applied; `old` their labels before) put on a region's
  // boundary has its centroid within kMaxSag·Δ of ∂Ω.
  bool new_boundary_near_surface(const std::vector<Move>& moves,
                                 const std::vector<domain::Label>& old);
  // Whether the facet's centroid lies within `bound` of ∂Ω.
  bool facet_near_surface(const std::array<mesh4d::VertexId, 4>& facet, double bound) const;
  // The options of one tier at f: 0 single pentatopes, 1 facet-adjacent pairs (both through one
  // of the `focus` vertices when there are any: link_trouble()), 2 the pieces, 3 the complements
  // of balls in the link.
  std::vector<std::vector<Move>> options_at(const NonManifoldVertex& f,
                                            const std::vector<delaunay::CellId>& star, int tier,
                                            const std::vector<mesh4d::VertexId>& focus) const;

  RefinementState& state_;
  const PinchScan& scan_;
  std::unordered_map<mesh4d::VertexId, std::vector<delaunay::CellId>> stars_;
  std::unordered_map<std::uint64_t, bool> current_;  // (vertex << 16 | label) -> fails
  std::vector<mesh4d::VertexId> touched_;            // vertices of the pentatopes moved this round
  std::vector<Move> journal_;                        // applied moves, with the label each left
  // While apply_mended mends: every move applied, with the label it left (undone in reverse, it
  // gives back the labels from before, whatever the mending undid itself meanwhile).
  std::vector<Move>* undo_log_ = nullptr;
  // While piece matching mends around a cut: moves that give a pentatope guarded_label_ are
  // not allowed when guard_ holds after them (the cut piece joined again).
  std::function<bool()> guard_;
  domain::Label guarded_label_ = 0;
  // Facets (sorted vertices) already asked whether they lie near ∂Ω, and the answer.
  std::map<std::array<mesh4d::VertexId, 4>, bool> near_facets_;
};

}  // namespace mesh4d::refine
