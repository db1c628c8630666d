#include "refine/rules.h"

#include <algorithm>
#include <cmath>
#include <random>

#include "refine/worker.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::kInfiniteVertex;
using delaunay::VertexKind;
using mesh4d::VertexId;

std::array<Rule, kQueuedRules> priority_order(RuleOrder order) {
  using enum Rule;
  return order == RuleOrder::r3_first ? std::array<Rule, kQueuedRules>{R3, R1, R2, R4, sizing, R5}
                                      : std::array<Rule, kQueuedRules>{R1, R2, R3, R4, sizing, R5};
}

Rules::Rules(RefinementState& state) : state_(state), params_(state.params) {}

bool Rules::cfp_dismissed(CellId c, Point4 a, Point4 b) const {
  // Only the part of [a, b] inside the circumball can hold an R1 point (a cfp beyond the ball
  // means the ball does not meet ∂Ω): the roots of |a + t (b − a) − center|² = r², with the
  // radius grown a little against rounding.
  const CellInfo& info = state_.info[c];
  const Point4 u{b[0] - a[0], b[1] - a[1], b[2] - a[2], b[3] - a[3]};
  const Point4 w{a[0] - info.center[0], a[1] - info.center[1], a[2] - info.center[2],
                 a[3] - info.center[3]};
  const double uu = u[0] * u[0] + u[1] * u[1] + u[2] * u[2] + u[3] * u[3];
  const double uw = u[0] * w[0] + u[1] * w[1] + u[2] * w[2] + u[3] * w[3];
  const double ww = w[0] * w[0] + w[1] * w[1] + w[2] * w[2] + w[3] * w[3];
  const double r = info.radius * (1 + 1e-9);
  if (uu > 0) {
    const double disc = uw * uw - uu * (ww - r * r);
    if (disc <= 0) return true;  // the line misses the ball
    const double root = std::sqrt(disc);
    const double t0 = std::max(0.0, (-uw - root) / uu), t1 = std::min(1.0, (-uw + root) / uu);
    if (t0 >= t1) return true;  // the segment misses it
    const Point4 a0 = a;
    for (int k = 0; k < 4; ++k) a[k] = a0[k] + t0 * u[k], b[k] = a0[k] + t1 * u[k];
  } else if (ww >= r * r) {
    return true;
  }
  // Strictly within Δ of both ends (with room for rounding), so of every point between: the
  // ball is convex. The pentatope's own feature vertices first: on the ventricle they find 98 %
  // of what the whole index finds.
  const double reach = params_.delta * (1 - 1e-9);
  const double reach2 = reach * reach;
  const auto covers = [&](const Point4& f) {
    return squared_distance(f, a) < reach2 && squared_distance(f, b) < reach2;
  };
  const auto& st = state_.tri.store();
  for (VertexId v : st.cell(c).v)
    if (v != kInfiniteVertex && st.vertex(v).kind == VertexKind::feature && covers(st.point(v)))
      return true;
  std::shared_lock lock(state_.features_mutex);
  return state_.features.any_within_own_cell_such(a, reach, covers);
}

bool Rules::ball_meets_surface(CellId c, domain::SurfaceBracket* cfp) const {
  const CellInfo& info = state_.info[c];
  if (info.surface_lower >= info.radius) return false;
  // The paper's cfp (ray to the nearest surface voxel, then bisection): the descent to the exact
  // closest point costs ten times more and changes little for sampling. Bracketed to 1/32 of a
  // voxel: R1 pinpoints it only when it inserts it. state_.label_of(c) is the label at the center
  // here: relabeling (the only other writer) runs after the rules, and the pentatopes it moves are
  // never queued again (only new pentatopes are).
  //
  // Below 2Δ (no R2) only an R1 point matters: R1 needs a cfp inside the ball and farther than
  // Δ from every feature vertex. When no place where the candidates can lie passes, before or
  // after the walk, the search stops (nine in ten searches on the ventricle end without one).
  class Covered final : public domain::SurfaceOracle::Dismissal {
   public:
    Covered(const Rules& rules, CellId cell) : rules_(rules), cell_(cell) {}
    bool drops(const Point4& a, const Point4& b) const override {
      return rules_.cfp_dismissed(cell_, a, b);
    }

   private:
    const Rules& rules_;
    CellId cell_;
  };
  const Covered covered(*this, c);
  bool dropped = false;
  const auto z = state_.oracle.closest_surface_bracket(
      info.center, {state_.label_of(c), info.surface_voxel, info.surface_lower},
      info.radius < 2 * params_.delta ? &covered : nullptr, &dropped);
  if (!z) return false;  // dropped, or no surface point found near the feature voxel
  *cfp = *z;
  return distance(info.center, z->middle().point) < info.radius;
}

bool Rules::has_restricted_non_feature_facet(CellId c) const {
  // A facet is restricted when the labels at the circumcenters of its two pentatopes differ
  // (its Voronoi edge crosses ∂Ω). Checked from both sides' cached labels, so that a facet whose
  // crossing lies outside this pentatope's circumball (inside the neighbor's) is still found.
  const auto& st = state_.tri.store();
  const auto& cell = st.cell(c);
  const domain::Label own = state_.label_of(c);
  for (int i = 0; i < 5; ++i) {
    const CellId n = cell.n[i];
    if (!state_.info[n].finite || state_.label_of(n) == own) continue;
    for (int k = 0; k < 5; ++k)
      if (k != i && st.vertex(cell.v[k]).kind != VertexKind::feature) return true;
  }
  return false;
}

Rule Rules::quick_rule(CellId c) const {
  const CellInfo& info = state_.info[c];
  if (!info.finite) return Rule::none;
  const double r = info.radius;
  // The label only where it decides (most new pentatopes are queued for R1 without it).
  if (params_.rule_order == RuleOrder::r3_first && info.long_radius && state_.label_of(c) != 0)
    return Rule::R3;
  // Not yet known, the distance to ∂Ω is taken as short: classify() reads it. (Computing it
  // here kept 0.1–0.4 % of the new pentatopes out of the queues on the ventricle and Pat04.)
  if (!info.surface_known || info.surface_lower < r) return Rule::R1;
  const bool inside = state_.label_of(c) != 0;
  if (inside && info.long_radius) return Rule::R3;
  if (inside && delaunay::normalized_volume(state_.simplex_of(c), r) < params_.sliver_bound)
    return Rule::R4;
  if (inside && params_.max_interior_radius > 0 && r > params_.max_interior_radius)
    return Rule::sizing;
  if (has_restricted_non_feature_facet(c)) return Rule::R5;
  return Rule::none;
}

Decision Rules::classify(Worker& w, CellId c) {
  Decision d;
  const auto decided = [&d](Rule rule) {
    d.rule = rule;
    return d;
  };
  CellInfo& info = state_.info[c];
  if (!info.finite) return d;
  // The neighbors' labels are read last (find_restricted_facet), after the cfp: their loads
  // start now.
  for (CellId n : state_.tri.store().cell(c).n) __builtin_prefetch(&state_.info[n]);
  if (!info.surface_known) {
    // What R1's cfp reads about the center. In a parallel phase this thread holds c.
    const auto facts = state_.oracle.facts(info.center, state_.label_of(c));
    info.surface_lower = facts.lower;
    info.surface_voxel = facts.surface_voxel;
    info.surface_known = true;
  }
  const Point4 center = info.center;
  const double r = info.radius;
  const bool inside = state_.label_of(c) != 0;
  const bool bad_ratio = inside && info.long_radius;
  d.point = center;
  if (params_.rule_order == RuleOrder::r3_first && bad_ratio) return decided(Rule::R3);
  // A feature vertex f with |center − f| + r < Δ puts the whole ball within Δ of f: then no
  // surface point in it can be an R1 point, and r < Δ rules out R2; skip the cfp. Only f in
  // center's own cell of the feature index are tried: they are 95 % of those found by a full
  // search (ventricle and Pat01), for a sixteenth of the work, and the full search found one
  // for 1 % of the pentatopes on the ventricle (15 % on Pat01).
  domain::SurfaceBracket z;
  if ((r >= params_.delta || !state_.feature_within(center, params_.delta - r, true)) &&
      ball_meets_surface(c, &z)) {
    if (!state_.feature_within(z.middle().point, params_.delta)) {
      d.sample = z.middle().point;
      d.point = state_.oracle.pinpoint(z).point;
      d.kind = VertexKind::feature;
      return decided(Rule::R1);
    }
    if (r >= 2 * params_.delta) {
      d.point = state_.clamp_to_box(center);
      if (d.point != center) d.kind = VertexKind::box;
      return decided(Rule::R2);
    }
  }
  if (bad_ratio) return decided(Rule::R3);
  if (inside && delaunay::normalized_volume(state_.simplex_of(c), r) < params_.sliver_bound) {
    d.point = pick_from_region(w, c, center, r);
    return decided(Rule::R4);
  }
  if (inside && params_.max_interior_radius > 0 && r > params_.max_interior_radius)
    return decided(Rule::sizing);
  Point4 surface_center;
  double surface_radius;
  if (find_restricted_facet(c, &surface_center, &surface_radius)) {
    d.point = pick_on_surface(w, c, surface_center, surface_radius);
    d.kind = VertexKind::feature;
    return decided(Rule::R5);
  }
  return d;
}

bool Rules::find_restricted_facet(CellId c, Point4* surface_center, double* surface_radius) const {
  // A facet is restricted when its Voronoi edge, the segment between the circumcenters of its
  // two pentatopes, crosses ∂Ω (the labels at its ends differ; that is also exactly when the
  // facet separates output pentatopes of different labels). R5 applies when such a facet has a
  // vertex that is not on ∂Ω.
  const auto& st = state_.tri.store();
  const auto& cell = st.cell(c);
  const CellInfo& own = state_.info[c];
  const domain::Label own_label = state_.label_of(c);
  for (int i = 0; i < 5; ++i) {
    // The neighbor's label first: most facets are not restricted, and it is one read.
    const CellId n = cell.n[i];
    if (!state_.info[n].finite || state_.label_of(n) == own_label) continue;
    bool all_feature = true;
    for (int k = 0; k < 5; ++k)
      if (k != i) all_feature &= st.vertex(cell.v[k]).kind == VertexKind::feature;
    if (all_feature) continue;
    const auto z = state_.oracle.first_crossing(own.center, state_.info[n].center);
    if (!z) continue;
    *surface_center = z->point;
    // z is on the Voronoi edge, equidistant from the facet's vertices.
    *surface_radius = distance(z->point, st.point(cell.v[(i + 1) % 5]));
    return true;
  }
  return false;
}

double Rules::worst_new_quality(Worker& w, const Point4& p, CellId hint) {
  // The cavity is computed, not committed.
  const VertexId next_id =
      w.guard ? kProvisionalId : static_cast<VertexId>(state_.tri.store().vertex_slots());
  const CellId located = state_.tri.locate(p, hint, *w.ws, w.guard);
  if (located == delaunay::kNoCell) return w.conflict = true, -1;
  if (!state_.tri.store().is_infinite(located))
    for (VertexId v : state_.tri.store().cell(located).v)
      if (state_.tri.store().point(v) == p) return -1;
  if (!state_.tri.find_cavity(p, next_id, located, w.trial, w.guard)) return w.conflict = true, -1;
  double worst = 1;
  for (const auto& f : w.trial.boundary) {
    if (state_.tri.store().is_infinite(f.cell)) continue;
    delaunay::Simplex4 s = state_.simplex_of(f.cell);
    s[f.index] = p;
    worst = std::min(worst, delaunay::normalized_volume(s));
  }
  return worst;
}

Point4 Rules::pick_on_surface(Worker& w, CellId c, const Point4& z, double radius) {
  // R5's picking region: points of ∂Ω within ζ·R of the surface center z. Trials are random
  // points of that ball pulled onto ∂Ω (cfp); z itself is the first.
  Point4 best = z;
  double best_quality = worst_new_quality(w, z, c);
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(0, 1);
  const double reach = params_.picking_ratio * radius;
  for (unsigned trial = 1;
       trial < params_.picking_trials && best_quality < params_.sliver_bound && !w.conflict;
       ++trial) {
    Point4 p;
    double n2 = 0;
    for (double& x : p) x = gauss(w.rng), n2 += x * x;
    const double scale = reach * std::pow(uniform(w.rng), 0.25) / std::sqrt(n2);
    for (int k = 0; k < 4; ++k) p[k] = z[k] + scale * p[k];
    const domain::SurfacePoint sq =
        state_.oracle.closest_surface_point(p, domain::SurfaceOracle::CfpMode::ray);
    const Point4 q = sq.point;
    if (sq.inner == sq.outer || distance(q, z) > reach || q != state_.clamp_to_box(q)) continue;
    const double quality = worst_new_quality(w, q, c);
    if (quality > best_quality) best_quality = quality, best = q;
  }
  return best;
}

Point4 Rules::pick_from_region(Worker& w, CellId c, const Point4& center, double radius) {
  // R4's picking region: the ball of radius ζ·R around the circumcenter. Each trial point's
  // cavity is computed (without committing) and the new pentatopes it would make are measured;
  // the first point whose worst new pentatope is no sliver wins, else the best one tried.
  std::normal_distribution<double> gauss;
  std::uniform_real_distribution<double> uniform(0, 1);
  Point4 best = center;
  double best_quality = -1;
  for (unsigned trial = 0; trial < params_.picking_trials; ++trial) {
    Point4 p;
    double n2 = 0;
    for (double& x : p) x = gauss(w.rng), n2 += x * x;
    // Uniform in the 4-ball: radius ∝ u^(1/4).
    const double scale =
        params_.picking_ratio * radius * std::pow(uniform(w.rng), 0.25) / std::sqrt(n2);
    for (int k = 0; k < 4; ++k) p[k] = center[k] + scale * p[k];
    if (p != state_.clamp_to_box(p)) continue;
    const double worst = worst_new_quality(w, p, c);
    if (w.conflict) break;
    if (worst < 0) continue;
    if (worst > best_quality) best_quality = worst, best = p;
    if (worst >= params_.sliver_bound) break;
  }
  return best;
}

}  // namespace mesh4d::refine
