// The rules R1–R5 and the interior sizing bound (docs/algorithm.md, "Rules"; the paper's Section
// 3): which one a pentatope calls for, and the point whose insertion applies it. R4 and R5 choose
// that point in a picking region, by the quality of the pentatopes each trial point would make.
#pragma once

#include <array>
#include <cstdint>

#include "delaunay/triangulation.h"
#include "refine/refine_params.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {

enum class Rule : std::uint8_t { R1, R2, R3, R4, R5, sizing, none };
/// The rules that queue pentatopes (all but none); counters of insertions know R1–R5 only.
inline constexpr int kQueuedRules = 6;
constexpr int index_of(Rule r) {
  return static_cast<int>(r);
}
/// The order in which queued rules are applied: R3 first, or the paper's R1…R5; sizing before
/// R5 in both.
std::array<Rule, kQueuedRules> priority_order(RuleOrder order);

/// What to do with a pentatope: the rule, the point to insert and its kind; for R1 also the
/// surface point whose Δ-ball was found free of feature vertices (before pinpointing).
struct Decision {
  Rule rule = Rule::none;
  Point4 point{};
  delaunay::VertexKind kind = delaunay::VertexKind::free;
  Point4 sample{};
};

struct Worker;

class Rules {
 public:
  explicit Rules(RefinementState& state);

  /// A cheap guess of a new pentatope's rule, for its queue; classify() confirms it when popped.
  Rule quick_rule(delaunay::CellId c) const;
  /// The rule that applies to a live pentatope and its point. Sets w.conflict on another
  /// thread's lock (a picking region's trial met it).
  Decision classify(Worker& w, delaunay::CellId c);

 private:
  bool has_restricted_non_feature_facet(delaunay::CellId c) const;
  bool find_restricted_facet(delaunay::CellId c, Point4* surface_center,
                             double* surface_radius) const;
  // Whether no point of segment [a, b] can be an R1 point of pentatope c: the part inside its
  // circumball (if any) lies strictly within Δ of one feature vertex. False may be a missed
  // one: only the pentatope's own vertices and one cell of the index are tried.
  bool cfp_dismissed(delaunay::CellId c, Point4 a, Point4 b) const;
  // Whether pentatope c's circumball meets ∂Ω, judged at the cfp of its center; for a ball
  // smaller than 2Δ, also false where the cfp is sure to be within Δ of a feature vertex.
  bool ball_meets_surface(delaunay::CellId c, domain::SurfaceBracket* cfp) const;
  Point4 pick_from_region(Worker& w, delaunay::CellId c, const Point4& center, double radius);
  Point4 pick_on_surface(Worker& w, delaunay::CellId c, const Point4& z, double radius);
  // The normalized volume of the worst pentatope that inserting p would make; -1 for a point
  // equal to a vertex, or (with w.conflict set) on another thread's lock.
  double worst_new_quality(Worker& w, const Point4& p, delaunay::CellId hint);

  RefinementState& state_;
  const RefineParams& params_;
};

}  // namespace mesh4d::refine
