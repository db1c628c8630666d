// One failing (vertex, label) pair's repair in the manifold step (manifold_relabeling.h): the
// cheapest set of pentatopes of the vertex's star whose move to a neighbor's label mends the
// vertex's link and lowers the number of failing pairs around it, tier by tier, with a detour
// one level deep. A LinkRepair holds one repair's working memory (stars, link answers, the
// journal of moves), so that repairs far enough apart can run at once, each on its own.
//
// What a repair at vertex v reads and writes: it moves pentatopes of the stars of v and of v's
// neighbors (the detour mends those), and it reads the labels of the pentatopes on vertices at
// most two edges from v. Two repairs whose vertices are five or more edges apart therefore
// neither read nor write what the other writes: run in either order, or at once, they give the
// same labels (RepairClaims).
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <unordered_map>
#include <vector>

#include "refine/manifold_scan.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

struct LabelMove {
  delaunay::CellId cell;
  domain::Label to;
};

class LinkRepair {
 public:
  LinkRepair(RefinementState& state, const PinchScan& scan) : state_(state), scan_(scan) {}

  /// gain_of() of moves of which one may not move.
  static constexpr long kNotAllowed = std::numeric_limits<long>::min();

  /// The best moves found around f, applied; false when none helps.
  bool repair(const NonManifoldVertex& f);
  /// How many failing pairs `moves` removes; kNotAllowed when one of them may not move.
  long gain_of(const std::vector<LabelMove>& moves);
  /// Whether `moves` pinch no triangle more and keep their new boundary facets near ∂Ω; with
  /// `pinches_mended`, only the latter (a pinched triangle fails its vertices' links, which the
  /// caller then requires mended).
  bool acceptable(const std::vector<LabelMove>& moves, bool pinches_mended = false);
  /// Failing (vertex, label) pairs over the moved pentatopes' vertices and `labels`; `current`:
  /// with the labels as they are (remembered until forget_links()).
  long failing_over(const std::vector<LabelMove>& moves, const std::vector<domain::Label>& labels,
                    bool current);

  /// Moves that give a pentatope `label` are not allowed while `guard` holds after them (nullptr:
  /// none).
  void set_guard(std::function<bool()> guard, domain::Label label) {
    guard_ = std::move(guard), guarded_label_ = label;
  }
  bool guarded() const { return static_cast<bool>(guard_); }
  /// Labels changed elsewhere: the stars and links remembered are forgotten.
  void forget_links() { stars_.clear(), current_.clear(); }
  /// Also the facets' distances to ∂Ω (the step is over).
  void forget_all() { forget_links(), near_facets_.clear(), journal_.clear(), touched_.clear(); }
  /// Pentatopes moved since the last take_moved(); the count is reset.
  std::size_t take_moved();
  /// The vertices of the pentatopes moved since the last take_touched(), with repeats.
  std::vector<mesh4d::VertexId> take_touched();

 private:
  // How many failing pairs the moves mended in all goes to *gained. depth > 0: a move that
  // mends f but breaks others may be followed by repairs of those, depth - 1 levels down.
  bool repair(const NonManifoldVertex& f, int depth, long* gained);
  // The star of u, kept while one failing vertex is repaired (labels change, stars do not).
  const std::vector<delaunay::CellId>& star_of(mesh4d::VertexId u);
  bool new_boundary_near_surface(const std::vector<LabelMove>& moves,
                                 const std::vector<domain::Label>& old);
  bool facet_near_surface(const std::array<mesh4d::VertexId, 4>& facet, double bound) const;
  std::vector<std::vector<LabelMove>> options_at(const NonManifoldVertex& f,
                                                 const std::vector<delaunay::CellId>& star,
                                                 int tier,
                                                 const std::vector<mesh4d::VertexId>& focus) const;
  void apply(const std::vector<LabelMove>& moves);
  void undo_to(std::size_t journal_mark, std::size_t touched_mark);

  RefinementState& state_;
  const PinchScan& scan_;
  std::unordered_map<mesh4d::VertexId, std::vector<delaunay::CellId>> stars_;
  std::unordered_map<std::uint64_t, bool> current_;  // (vertex << 16 | label) -> fails
  std::vector<mesh4d::VertexId> touched_;            // vertices of the pentatopes moved
  std::vector<LabelMove> journal_;                   // applied moves, with the label each left
  std::size_t moved_ = 0;
  std::function<bool()> guard_;
  domain::Label guarded_label_ = 0;
  // Facets (sorted vertices) already asked whether they lie near ∂Ω, and the answer (the
  // triangulation does not change during the step).
  std::map<std::array<mesh4d::VertexId, 4>, bool> near_facets_;
};

/// The vertices within two edges of a failing pair's vertex (in periodic time each also as
/// counted_vertex() has it): two repairs whose claims share no vertex may run at once. One per
/// thread.
class RepairClaims {
 public:
  explicit RepairClaims(const RefinementState& state)
      : state_(state), seen_(state.tri.store().vertex_slots(), 0) {}
  void claim(mesh4d::VertexId v, std::vector<mesh4d::VertexId>& claim);

 private:
  const RefinementState& state_;
  std::vector<std::uint32_t> seen_;  // per vertex: the stamp of the claim that holds it
  std::uint32_t stamp_ = 0;
  std::vector<delaunay::CellId> star_;
};

}  // namespace mesh4d::refine
