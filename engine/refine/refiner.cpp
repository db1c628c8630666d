#include "refine/refiner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "delaunay/circumballs.h"
#include "delaunay/geometry.h"
#include "refine/repair_policy.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::kInfiniteVertex;
using delaunay::VertexKind;
using mesh4d::VertexId;

namespace {

constexpr auto kReportInterval = std::chrono::milliseconds(200);
constexpr int kRepairRounds = 40;  // of pinch repair, each followed by the rules
constexpr int kUnpinchRounds = 4;  // of free-vertex removal where relabeling is stuck
// The id a trial point's cavity is computed with in a parallel phase, where the next id is not
// known: the newest of all, as the point would be in a sequential run.
constexpr VertexId kProvisionalId = delaunay::kNoVertex - 1;

}  // namespace

Refiner::Refiner(const domain::SurfaceOracle& oracle, const RefineParams& params)
    : oracle_(oracle), params_(params), features_(params.delta) {
  validate(params_);
  workers_.push_back(std::make_unique<Worker>(tri_, 0, params_.seed));
  workers_[0]->ws = &tri_.workspace();
}

void Refiner::insert_box() {
  // The bounding box of the foreground voxels, grown so that its corners are at least 2Δ from
  // ∂Ω (which lies within a voxel-cell diagonal of foreground voxel centers).
  const domain::LabelImage4& image = oracle_.image();
  const auto& d = image.dims();
  std::array<std::size_t, 4> lo{d[0], d[1], d[2], d[3]}, hi{0, 0, 0, 0};
  for (std::size_t t = 0, i = 0; t < d[3]; ++t)
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x, ++i) {
          if (image.at(i) == 0) continue;
          const std::size_t c[4] = {x, y, z, t};
          for (int a = 0; a < 4; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
        }
  double diagonal = 0;
  for (double s : image.spacing()) diagonal += s * s;
  const double margin = 2 * params_.delta + std::sqrt(diagonal);
  const Point4 a = image.voxel_center(lo[0], lo[1], lo[2], lo[3]);
  const Point4 b = image.voxel_center(hi[0], hi[1], hi[2], hi[3]);
  for (int k = 0; k < 4; ++k) box_[0][k] = a[k] - margin, box_[1][k] = b[k] + margin;
  for (int corner = 0; corner < 16; ++corner) {
    Point4 p;
    for (int k = 0; k < 4; ++k) p[k] = box_[(corner >> k) & 1][k];
    tri_.insert(p, VertexKind::box);
  }
}

Point4 Refiner::clamp_to_box(const Point4& p) const {
  Point4 q;
  for (int k = 0; k < 4; ++k) q[k] = std::clamp(p[k], box_[0][k], box_[1][k]);
  return q;
}

bool Refiner::cfp_dismissed(CellId c, Point4 a, Point4 b) const {
  // Only the part of [a, b] inside the circumball can hold an R1 point (a cfp beyond the ball
  // means the ball does not meet ∂Ω): the roots of |a + t (b − a) − center|² = r², with the
  // radius grown a little against rounding.
  const CellInfo& info = info_[c];
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
  const auto& st = tri_.store();
  for (VertexId v : st.cell(c).v)
    if (v != kInfiniteVertex && st.vertex(v).kind == VertexKind::feature && covers(st.point(v)))
      return true;
  std::shared_lock lock(features_mutex_);
  return features_.any_within_own_cell_such(a, reach, covers);
}

bool Refiner::ball_meets_surface(CellId c, domain::SurfaceBracket* cfp) const {
  const CellInfo& info = info_[c];
  if (info.surface_lower >= info.radius) return false;
  // The paper's cfp (ray to the nearest surface voxel, then bisection): the descent to the exact
  // closest point costs ten times more and changes little for sampling. Bracketed to 1/32 of a
  // voxel: R1 pinpoints it only when it inserts it. label_of(c) is the label at the center here:
  // relabeling (the only other writer) runs after the rules, and the pentatopes it moves are
  // never queued again (only new pentatopes are).
  //
  // Below 2Δ (no R2) only an R1 point matters: R1 needs a cfp inside the ball and farther than
  // Δ from every feature vertex. When no place where the candidates can lie passes, before or
  // after the walk, the search stops (nine in ten searches on the ventricle end without one).
  class Covered final : public domain::SurfaceOracle::Dismissal {
   public:
    Covered(const Refiner& refiner, CellId cell) : refiner_(refiner), cell_(cell) {}
    bool drops(const Point4& a, const Point4& b) const override {
      return refiner_.cfp_dismissed(cell_, a, b);
    }

   private:
    const Refiner& refiner_;
    CellId cell_;
  };
  const Covered covered(*this, c);
  bool dropped = false;
  const auto z = oracle_.closest_surface_bracket(
      info.center, {label_of(c), info.surface_voxel, info.surface_lower},
      info.radius < 2 * params_.delta ? &covered : nullptr, &dropped);
  if (!z) return false;  // dropped, or no surface point found near the feature voxel
  *cfp = *z;
  return distance(info.center, z->middle().point) < info.radius;
}

void Refiner::update_infos(const std::vector<CellId>& cells) {
  // The finite pentatopes' circumballs four at a time (circumballs4: the same numbers as one
  // at a time, faster); a short last group is padded with its first pentatope.
  const auto& st = tri_.store();
  CellId group[4];
  const Point4* vertices[4][5];
  int n = 0;
  const auto measure = [&] {
    for (int l = n; l < 4; ++l) std::copy(vertices[0], vertices[0] + 5, vertices[l]);
    delaunay::Circumball balls[4];
    delaunay::circumballs4(vertices, balls);
    for (int l = 0; l < n; ++l) {
      CellInfo& info = info_[group[l]];
      info.center = balls[l].center;
      if (!std::isfinite(info.center[0])) continue;  // flat: not finite
      info.radius = balls[l].radius;
      // Rounded up to a float: a conversion moves a normal value by at most 2⁻²⁴ of it.
      const double e = balls[l].center_error;
      info.center_error = e < 1e-30 ? 1e-30f : static_cast<float>(e * (1 + 0x1p-20));
      info.long_radius = info.radius / balls[l].shortest_edge >= params_.radius_edge_bound;
      info.label_code = 0;
      info.surface_known = false;
      info.finite = true;
    }
    n = 0;
  };
  for (CellId c : cells) {
    info_.ensure(std::size_t{c} + 1);
    info_[c].finite = false;
    if (st.is_infinite(c)) continue;
    group[n] = c;
    for (int k = 0; k < 5; ++k) vertices[n][k] = &st.point(st.cell(c).v[k]);
    if (++n == 4) measure();
  }
  if (n > 0) measure();
}

void Refiner::decide(const CellId* cells, int count, const Point4& p, std::int8_t* verdict) const {
  for (int k = 0; k < count; ++k) {
    const CellInfo& info = info_[cells[k]];
    verdict[k] = info.finite ? static_cast<std::int8_t>(delaunay::ball_verdict(
                                   info.center, info.radius, info.center_error, p))
                             : 0;
  }
}

void Refiner::admit(Worker& w, const std::vector<CellId>& cells) {
  update_infos(cells);
  for (CellId c : cells) enqueue(w, c);
}

bool Refiner::has_restricted_non_feature_facet(CellId c) const {
  // A facet is restricted when the labels at the circumcenters of its two pentatopes differ
  // (its Voronoi edge crosses ∂Ω). Checked from both sides' cached labels, so that a facet whose
  // crossing lies outside this pentatope's circumball (inside the neighbor's) is still found.
  const auto& st = tri_.store();
  const auto& cell = st.cell(c);
  const domain::Label own = label_of(c);
  for (int i = 0; i < 5; ++i) {
    const CellId n = cell.n[i];
    if (!info_[n].finite || label_of(n) == own) continue;
    for (int k = 0; k < 5; ++k)
      if (k != i && st.vertex(cell.v[k]).kind != VertexKind::feature) return true;
  }
  return false;
}

Refiner::Rule Refiner::quick_rule(CellId c) const {
  const CellInfo& info = info_[c];
  if (!info.finite) return kNone;
  const double r = info.radius;
  // The label only where it decides (most new pentatopes are queued for R1 without it).
  if (params_.rule_order == RuleOrder::r3_first && info.long_radius && label_of(c) != 0) return kR3;
  // Not yet known, the distance to ∂Ω is taken as short: classify() reads it. (Computing it
  // here kept 0.1–0.4 % of the new pentatopes out of the queues on the ventricle and Pat04.)
  if (!info.surface_known || info.surface_lower < r) return kR1;
  const bool inside = label_of(c) != 0;
  if (inside && info.long_radius) return kR3;
  if (inside && delaunay::normalized_volume(simplex_of(c), r) < params_.sliver_bound) return kR4;
  if (inside && params_.max_interior_radius > 0 && r > params_.max_interior_radius) return kSizing;
  if (has_restricted_non_feature_facet(c)) return kR5;
  return kNone;
}

Refiner::Rule Refiner::classify(Worker& w, CellId c, Point4* point, VertexKind* kind) {
  CellInfo& info = info_[c];
  if (!info.finite) return kNone;
  // The neighbors' labels are read last (find_restricted_facet), after the cfp: their loads
  // start now.
  for (CellId n : tri_.store().cell(c).n) __builtin_prefetch(&info_[n]);
  if (!info.surface_known) {
    // What R1's cfp reads about the center. In a parallel phase this thread holds c.
    const auto facts = oracle_.facts(info.center, label_of(c));
    info.surface_lower = facts.lower;
    info.surface_voxel = facts.surface_voxel;
    info.surface_known = true;
  }
  const Point4 center = info.center;
  const double r = info.radius;
  const bool inside = label_of(c) != 0;
  const bool bad_ratio = inside && info.long_radius;
  *kind = VertexKind::free;
  *point = center;
  if (params_.rule_order == RuleOrder::r3_first && bad_ratio) return kR3;
  // A feature vertex f with |center − f| + r < Δ puts the whole ball within Δ of f: then no
  // surface point in it can be an R1 point, and r < Δ rules out R2; skip the cfp. Only f in
  // center's own cell of the feature index are tried: they are 95 % of those found by a full
  // search (ventricle and Pat01), for a sixteenth of the work, and the full search found one
  // for 1 % of the pentatopes on the ventricle (15 % on Pat01).
  domain::SurfaceBracket z;
  if ((r >= params_.delta || !feature_within(center, params_.delta - r, true)) &&
      ball_meets_surface(c, &z)) {
    if (!feature_within(z.middle().point, params_.delta)) {
      w.r1_sample = z.middle().point;
      *point = oracle_.pinpoint(z).point;
      *kind = VertexKind::feature;
      return kR1;
    }
    if (r >= 2 * params_.delta) {
      *point = clamp_to_box(center);
      if (*point != center) *kind = VertexKind::box;
      return kR2;
    }
  }
  if (bad_ratio) return kR3;
  if (inside && delaunay::normalized_volume(simplex_of(c), r) < params_.sliver_bound) {
    *point = pick_from_region(w, c, center, r);
    return kR4;
  }
  if (inside && params_.max_interior_radius > 0 && r > params_.max_interior_radius) return kSizing;
  Point4 surface_center;
  double surface_radius;
  if (find_restricted_facet(c, &surface_center, &surface_radius)) {
    *point = pick_on_surface(w, c, surface_center, surface_radius);
    *kind = VertexKind::feature;
    return kR5;
  }
  return kNone;
}

bool Refiner::find_restricted_facet(CellId c, Point4* surface_center,
                                    double* surface_radius) const {
  // A facet is restricted when its Voronoi edge, the segment between the circumcenters of its
  // two pentatopes, crosses ∂Ω (the labels at its ends differ; that is also exactly when the
  // facet separates output pentatopes of different labels). R5 applies when such a facet has a
  // vertex that is not on ∂Ω.
  const auto& st = tri_.store();
  const auto& cell = st.cell(c);
  const CellInfo& own = info_[c];
  const domain::Label own_label = label_of(c);
  for (int i = 0; i < 5; ++i) {
    // The neighbor's label first: most facets are not restricted, and it is one read.
    const CellId n = cell.n[i];
    if (!info_[n].finite || label_of(n) == own_label) continue;
    bool all_feature = true;
    for (int k = 0; k < 5; ++k)
      if (k != i) all_feature &= st.vertex(cell.v[k]).kind == VertexKind::feature;
    if (all_feature) continue;
    const auto z = oracle_.first_crossing(own.center, info_[n].center);
    if (!z) continue;
    *surface_center = z->point;
    // z is on the Voronoi edge, equidistant from the facet's vertices.
    *surface_radius = distance(z->point, st.point(cell.v[(i + 1) % 5]));
    return true;
  }
  return false;
}

double Refiner::worst_new_quality(Worker& w, const Point4& p, CellId hint) {
  // The normalized volume of the worst pentatope that inserting p would create (its cavity is
  // computed, not committed); -1 for a point equal to a vertex.
  const VertexId next_id =
      w.guard ? kProvisionalId : static_cast<VertexId>(tri_.store().vertex_slots());
  const CellId located = tri_.locate(p, hint, *w.ws, w.guard);
  if (located == delaunay::kNoCell) return w.conflict = true, -1;
  if (!tri_.store().is_infinite(located))
    for (VertexId v : tri_.store().cell(located).v)
      if (tri_.store().point(v) == p) return -1;
  if (!tri_.find_cavity(p, next_id, located, w.trial, w.guard)) return w.conflict = true, -1;
  double worst = 1;
  for (const auto& f : w.trial.boundary) {
    if (tri_.store().is_infinite(f.cell)) continue;
    delaunay::Simplex4 s = simplex_of(f.cell);
    s[f.index] = p;
    worst = std::min(worst, delaunay::normalized_volume(s));
  }
  return worst;
}

Point4 Refiner::pick_on_surface(Worker& w, CellId c, const Point4& z, double radius) {
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
        oracle_.closest_surface_point(p, domain::SurfaceOracle::CfpMode::ray);
    const Point4 q = sq.point;
    if (sq.inner == sq.outer || distance(q, z) > reach || q != clamp_to_box(q)) continue;
    const double quality = worst_new_quality(w, q, c);
    if (quality > best_quality) best_quality = quality, best = q;
  }
  return best;
}

bool Refiner::claim_free_vertices_near(Worker& w, const Point4& p) {
  // R5's second half: free vertices closer than Δ to the new surface point go, so that the
  // surface is not approached too closely from inside (feature and box vertices stay). The new
  // point's neighbors are exactly the vertices of its cavity. In a parallel phase their stars
  // are claimed now, before the insertion commits: every pentatope the removals then touch is
  // one of those or is made of claimed vertices, so the removals cannot meet a lock.
  const auto& st = tri_.store();
  w.near.clear();
  for (CellId c : w.ws->cavity.cells)
    for (VertexId u : st.cell(c).v)
      if (u != kInfiniteVertex && st.vertex(u).kind == VertexKind::free &&
          distance(st.point(u), p) < params_.delta &&
          std::find(w.near.begin(), w.near.end(), u) == w.near.end())
        w.near.push_back(u);
  if (w.guard)
    for (VertexId u : w.near)
      if (!tri_.incident_cells(u, w.star, w.guard)) return false;
  return true;
}

Point4 Refiner::pick_from_region(Worker& w, CellId c, const Point4& center, double radius) {
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
    if (p != clamp_to_box(p)) continue;
    const double worst = worst_new_quality(w, p, c);
    if (w.conflict) break;
    if (worst < 0) continue;
    if (worst > best_quality) best_quality = worst, best = p;
    if (worst >= params_.sliver_bound) break;
  }
  return best;
}

void Refiner::enqueue(Worker& w, CellId c) {
  if (!tri_.store().is_live(c) || tri_.store().is_infinite(c)) return;
  const Rule rule = quick_rule(c);
  if (rule == kNone) return;
  Candidate k{c, {}};
  for (int i = 0; i < 5; ++i) k.v[i] = tri_.store().cell(c).v[i];
  if (!w.guard) {
    w.queues[rule].push_back(k);
    return;
  }
  std::lock_guard lock(w.queue_mutex);
  w.queues[rule].push_back(k);
  w.publish_length(rule);
}

bool Refiner::still_valid(const Candidate& k) const {
  return tri_.store().still_holds(k.cell, k.v);
}

Progress Refiner::totals() const {
  Progress sum = progress_;
  for (const auto& w : workers_) {
    for (int r = 0; r < 5; ++r) {
      sum.insertions[r] += w->insertions[r].load(std::memory_order_relaxed);
      sum.removals[r] += w->removals[r].load(std::memory_order_relaxed);
    }
    sum.rollbacks += w->rollbacks.load(std::memory_order_relaxed);
    sum.contention_seconds += 1e-9 * double(w->contention_ns.load(std::memory_order_relaxed));
    sum.idle_seconds += 1e-9 * double(w->idle_ns.load(std::memory_order_relaxed));
  }
  return sum;
}

void Refiner::report(ProgressSink* sink, Phase phase, bool force) {
  const auto now = std::chrono::steady_clock::now();
  if (!sink || (!force && now - last_report_ < kReportInterval)) return;
  last_report_ = now;
  Progress p = totals();
  p.phase = phase;
  p.vertices = tri_.number_of_vertices();
  // Includes the few infinite ones (cheap); in a parallel phase, the workers' counts added.
  std::int64_t cells = static_cast<std::int64_t>(tri_.number_of_cells());
  if (workers_[0]->guard)
    for (const auto& w : workers_) cells += w->live_cells.load(std::memory_order_relaxed);
  p.pentatopes = static_cast<std::uint64_t>(std::max<std::int64_t>(cells, 0));
  p.elapsed_seconds = std::chrono::duration<double>(now - start_).count();
  sink->on_progress(p);
}

Refiner::Outcome Refiner::insert_and_admit(Worker& w, const Point4& point, VertexKind kind,
                                           CellId hint, int rule, const Point4* sample,
                                           double clearance) {
  if (tri_.number_of_vertices() >= params_.vertex_budget) {
    std::ostringstream s;
    s << "refinement needs more than the vertex budget of " << params_.vertex_budget
      << " vertices; raise vertex_budget or delta";
    throw BudgetExceeded(s.str());
  }
  for (double x : point)
    if (!std::isfinite(x)) throw std::logic_error("Refiner: non-finite point to insert");
  const auto& st = tri_.store();
  if (!w.guard && (hint == delaunay::kNoCell || !st.is_live(hint))) hint = tri_.any_cell();
  // The steps of Triangulation::insert, with the checks of a concurrent operation between
  // them: every lock is taken before the first write, so a conflict leaves nothing behind.
  const CellId start = tri_.locate(point, hint, *w.ws, w.guard);
  if (start == delaunay::kNoCell) return Outcome::conflict;
  if (!st.is_infinite(start))
    for (VertexId u : st.cell(start).v)
      if (st.point(u) == point) return Outcome::skipped;
  // The cavity is found with an id newer than any; the real id, taken only once nothing can
  // roll back any more, is newer than every vertex of the claimed pentatopes too (their
  // vertices were committed before this thread claimed them), so every tie-break is the same.
  if (!tri_.find_cavity(point, kProvisionalId, start, w.ws->cavity, w.guard))
    return Outcome::conflict;
  if (rule == kR5 && !claim_free_vertices_near(w, point)) return Outcome::conflict;
  if (kind == VertexKind::feature) {
    // Another thread may have sampled ∂Ω nearby since the rule was decided.
    std::unique_lock lock(features_mutex_);
    if (sample && features_.any_within(*sample, clearance < 0 ? params_.delta : clearance))
      return Outcome::conflict;
    features_.add(point);
  }
  const bool log_facets = counting_facets_;
  if (log_facets) note_doomed_facets(w, rule);
  const VertexId v = tri_.new_vertex(point, kind, w.guard ? w.locks.owner() : 0);
  if (w.guard) w.locks.adopt(v);
  tri_.commit(w.ws->cavity, v, *w.ws);
  w.insertions[rule].fetch_add(1, std::memory_order_relaxed);
  w.created.clear();
  if (rule == kR5)
    for (VertexId u : w.near)
      if (tri_.remove(u, &w.created, *w.ws, w.guard) ==
          delaunay::Triangulation::RemoveResult::removed) {
        w.removals[kR5].fetch_add(1, std::memory_order_relaxed);
        if (log_facets) w.removed.push_back(u);
      }
  // The new pentatopes: the star of the new vertex (what commit made, unless removals changed
  // it), and what filled removed vertices' holes (some of those may have died in a later
  // removal).
  // They are queued in the order commit made them, each once (the star's), or else sorted to
  // drop repeats. Sorting the star too cost 1.4 % of the hypersphere's time; the order only
  // picks which of equally checked meshes comes out (seeds 1-5, every row: 1 % fewer
  // pentatopes, 2 % less time).
  if (w.near.empty() || rule != kR5) {
    w.fresh.assign(w.ws->created.begin(), w.ws->created.end());
  } else {
    tri_.incident_cells(v, w.fresh);
    for (CellId c : w.created)
      if (st.is_live(c)) w.fresh.push_back(c);
    std::sort(w.fresh.begin(), w.fresh.end());
    w.fresh.erase(std::unique(w.fresh.begin(), w.fresh.end()), w.fresh.end());
  }
  admit(w, w.fresh);
  if (log_facets) {
    std::sort(w.fresh.begin(), w.fresh.end());  // log_facet_changes searches them
    log_facet_changes(w);
  }
  return Outcome::done;
}

Refiner::Outcome Refiner::process(Worker& w, const Candidate& k) {
  if (w.guard)
    for (VertexId u : k.v)
      if (!w.locks.lock(u)) return Outcome::conflict;
  if (!still_valid(k)) return Outcome::skipped;
  Point4 point;
  VertexKind kind;
  w.conflict = false;
  const Rule rule = classify(w, k.cell, &point, &kind);
  if (w.conflict) return Outcome::conflict;
  if (rule == kNone) return Outcome::skipped;
  // The computed circumcenter of a nearly degenerate pentatope (five surface points on one
  // voxel plane, nearly co-spherical) can lie outside its exact circumsphere; a point placed
  // from it then leaves the pentatope in place. Its centroid is inside it, so in conflict.
  const VertexId next_id =
      w.guard ? kProvisionalId : static_cast<VertexId>(tri_.store().vertex_slots());
  if (kind == VertexKind::free && !tri_.in_conflict(k.cell, point, next_id))
    point = centroid_of(k.cell);
  const Outcome outcome = insert_and_admit(w, point, kind, k.cell, rule == kSizing ? kR3 : rule,
                                           rule == kR1 ? &w.r1_sample : nullptr);
  // A pentatope that survives its operation (not in conflict with a surface point) is
  // classified again; each retry follows an insertion, so the vertex budget bounds them.
  if (outcome == Outcome::done && still_valid(k)) enqueue(w, k.cell);
  return outcome;
}

void Refiner::drain(ProgressSink* sink) {
  pinches_current_ = false;
  const auto t0 = std::chrono::steady_clock::now();
  if (params_.threads > 1)
    drain_parallel(sink);
  else
    drain_sequential(sink);
  rules_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void Refiner::drain_sequential(ProgressSink* sink) {
  // Priority: the order of the rules (R3 first by default), through one stack per rule.
  Worker& w = *workers_[0];
  const std::array<Rule, 6> order = params_.rule_order == RuleOrder::r3_first
                                        ? std::array<Rule, 6>{kR3, kR1, kR2, kR4, kSizing, kR5}
                                        : std::array<Rule, 6>{kR1, kR2, kR3, kR4, kSizing, kR5};
  while (true) {
    BlockStack<Candidate>* queue = nullptr;
    for (Rule r : order)
      if (!w.queues[r].empty()) {
        queue = &w.queues[r];
        break;
      }
    if (!queue) return;
    const Candidate k = queue->back();
    queue->pop_back();
    // The next candidate's pentatope was queued long ago: its loads start now.
    if (!queue->empty()) {
      __builtin_prefetch(&tri_.store().cell(queue->back().cell));
      __builtin_prefetch(&info_[queue->back().cell]);
    }
    if (!still_valid(k)) continue;
    if (++w.operations % 256 == 0) {
      if (sink && sink->should_abort()) throw Cancelled();
      report(sink, Phase::refining, false);
    }
    process(w, k);
  }
}

RefineResult Refiner::run(ProgressSink* sink) {
  start_ = last_report_ = std::chrono::steady_clock::now();
  tri_.set_conflict_filter(nullptr);  // the box's and junctions' pentatopes have no info yet
  insert_box();
  insert_junctions();
  std::vector<CellId> fresh;
  for (CellId c = 0; c < tri_.store().cell_slots(); ++c)
    if (tri_.store().is_live(c)) fresh.push_back(c);
  admit(fresh);
  // From here every live pentatope has its circumball.
  tri_.set_conflict_filter(this);
  drain(sink);
  // The rules' counts, also for a job that refines faster than the report interval.
  report(sink, Phase::refining, true);
  // Where three labels meet the rules guarantee no manifold boundary; sample more of ∂Ω there
  // and refine again. Points closer than half of Δ to a sampled one are allowed only when
  // nothing else is left or the count stalls, down to Δ/16, and a finer level that makes the
  // count grow ends the repair (RepairPolicy): the work stays bounded. (Starting at a quarter
  // of Δ, the short edges of the points squeezed in set off the radius-edge rule around them:
  // on the ventricle the repair then doubled the mesh after the rules, for the same fidelity.)
  const auto repair_start = std::chrono::steady_clock::now();
  double min_spacing = 0.5 * params_.delta;
  bool counted_since = false;  // the repair's last count is still current
  RepairPolicy policy;
  for (int round = 0; round < kRepairRounds && min_spacing >= params_.delta / 16;) {
    // The count a full scan gives (the first one is a scan; later ones follow the facets that
    // the round's insertions changed, which a test checks against scans).
    const std::size_t pinches = count_for_repair();
    counted_since = true;
    const RepairPolicy::Next next = policy.observe(pinches);
    if (next == RepairPolicy::Next::stop) break;
    if (next == RepairPolicy::Next::repair && repair_pinches(min_spacing) > 0) {
      counted_since = false;
      ++round;
      drain(sink);
      continue;
    }
    min_spacing /= 2;
    policy.finer();
  }
  if (counted_since) set_current_pinches(known_pinches_);
  counting_facets_ = false;
  pinch_counts_.clear();
  refused_.clear();
  for (auto& w : workers_) w->facet_changes.clear();
  const double repair_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - repair_start).count();

  // What the repair leaves, relabeling closes; where it cannot (a pentatope that would have to
  // move has a free vertex), those free vertices go, the rules run again, and so on, a few times.
  RefineResult result;
  result.relabeled = relabel_pinches();
  for (int round = 0; round < kUnpinchRounds && !current_pinches().empty(); ++round) {
    if (remove_free_vertices_at_pinches() == 0) break;
    drain(sink);
    result.relabeled += relabel_pinches();
  }
  report(sink, Phase::extracting, true);
  result.mesh = extract(result.warnings);
  if (const std::size_t pinches = current_pinches().size()) {
    std::ostringstream s;
    s << pinches << " boundary triangles are pinched (in four or more boundary tetrahedra of one "
      << "label) where labels meet; a smaller delta resolves more of them";
    result.warnings.push_back(s.str());
  }
  result.stats = mesh::compute_stats(result.mesh, params_.threads);
  const Progress done = totals();
  for (int r = 0; r < 5; ++r) {
    result.stats.insertions[r] = done.insertions[r];
    result.stats.removals[r] = done.removals[r];
  }
  result.rollbacks = done.rollbacks;
  result.contention_seconds = done.contention_seconds;
  result.idle_seconds = done.idle_seconds;
  result.rules_seconds = rules_seconds_;
  result.repair_seconds = repair_seconds;
  result.stats.elapsed_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  return result;
}

}  // namespace mesh4d::refine
