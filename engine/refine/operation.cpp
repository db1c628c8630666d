#include "refine/operation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "delaunay/geometry.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::kInfiniteVertex;
using delaunay::VertexKind;
using mesh4d::VertexId;

Operation::Operation(RefinementState& state, Rules& rules) : state_(state), rules_(rules) {}

void Operation::admit(Worker& w, const std::vector<CellId>& cells) {
  state_.admit(cells);
  if (!w.guard) {
    for (CellId c : cells) enqueue(w, c);
    return;
  }
  // In a parallel phase thieves take from the queues: they are locked once for the whole batch,
  // which is pushed in the same order.
  w.admitted.clear();
  for (CellId c : cells)
    if (const int rule = queue_of(c); rule >= 0) w.admitted.push_back({rule, state_.candidate(c)});
  if (w.admitted.empty()) return;
  std::lock_guard lock(w.queue_mutex);
  unsigned pushed = 0;  // a bit per queue
  for (const auto& [rule, k] : w.admitted) w.queues[rule].push_back(k), pushed |= 1u << rule;
  for (int r = 0; r < kQueuedRules; ++r)
    if (pushed >> r & 1) w.publish_length(r);
}

int Operation::queue_of(CellId c) const {
  if (!state_.tri.store().is_live(c) || state_.tri.store().is_infinite(c)) return -1;
  // In periodic time the rules run on each class's representative; its copies follow.
  if (!state_.covering.rules_apply(state_.tri, c)) return -1;
  const int rule = index_of(rules_.quick_rule(c));
  return rule == index_of(Rule::none) ? -1 : rule;
}

void Operation::enqueue(Worker& w, CellId c) {
  const int rule = queue_of(c);
  if (rule < 0) return;
  const Candidate k = state_.candidate(c);
  if (!w.guard) {
    w.queues[rule].push_back(k);
    return;
  }
  std::lock_guard lock(w.queue_mutex);
  w.queues[rule].push_back(k);
  w.publish_length(rule);
}

Outcome Operation::insert(Worker& w, const Point4& point, VertexKind kind, CellId hint, Rule rule,
                          const Point4* sample, double clearance) {
  if (state_.covering.active()) return insert_copies(w, point, kind, hint, rule, sample, clearance);
  return insert_one(w, point, kind, hint, rule, sample, clearance);
}

Outcome Operation::insert_copies(Worker& w, const Point4& point, VertexKind kind, CellId hint,
                                 Rule rule, const Point4* sample, double clearance) {
  if (w.guard && !w.exclusive)
    return insert_copies_claimed(w, point, kind, hint, rule, sample, clearance);
  // A point from the covering's cut-off ends would copy an artefact into the middle sheet.
  if (!state_.covering.trusted(point)) return Outcome::skipped;
  const auto& st = state_.tri.store();
  const std::array<Point4, 3> copies = state_.covering.copies(point);
  Outcome first = Outcome::skipped;
  std::vector<VertexId> removed;
  for (int s = 0; s < 3; ++s) {
    if (s > 0 && !state_.covering.in_covering(copies[s])) continue;
    // The hint pentatope lies in one sheet: the walk to the other copies starts from the
    // pentatope the last insertion made in theirs.
    CellId start = hint;
    if (start == delaunay::kNoCell || !st.is_live(start) ||
        std::abs(st.point(st.cell(start).v[0] == kInfiniteVertex ? st.cell(start).v[1]
                                                                 : st.cell(start).v[0])[3] -
                 copies[s][3]) > state_.covering.period().length / 2)
      start = sheet_hint_[s];
    if (w.guard) {
      // Alone in a parallel phase: no other thread holds a lock, so every claim succeeds.
      if (start == delaunay::kNoCell || !st.is_live(start)) start = state_.tri.any_cell();
      if (!w.guard->acquire(start)) return Outcome::conflict;
    }
    // Only the middle copy's sample is checked: the index holds every copy of each feature.
    Point4 shifted_sample;
    if (sample) shifted_sample = *sample, shifted_sample[3] += copies[s][3] - point[3];
    const Outcome o = insert_one(w, copies[s], kind, start, rule,
                                 sample && s == 0 ? &shifted_sample : nullptr, clearance);
    if (o == Outcome::done) {
      sheet_hint_[s] = w.fresh.empty() ? delaunay::kNoCell : w.fresh.front();
      removed.insert(removed.end(), w.removed.begin(), w.removed.end());
    } else if (s == 0 && o == Outcome::conflict) {
      return o;  // a feature already within the sample's ball: none of the copies goes in
    }
    if (s == 0) first = o;
  }
  if (rule == Rule::R5) remove_twins(w, removed);
  return first;
}

CellId Operation::twin_start(Worker& w, CellId hint, int periods, bool* none) {
  const auto& st = state_.tri.store();
  *none = false;
  for (VertexId u : st.cell(hint).v) {
    if (u == kInfiniteVertex) continue;
    Point4 p = st.point(u);
    p[3] += periods * state_.covering.period().length;
    VertexId t;
    {
      std::shared_lock lock(copies_mutex_);
      t = state_.covering.vertex_inserted_at(p);
    }
    if (t == delaunay::kNoVertex) continue;
    // Held, t's incident pentatope cannot change under this thread (only holders commit).
    if (!w.guard->lock(t)) return delaunay::kNoCell;
    const delaunay::Vertex& twin = st.vertex(t);
    if (twin.kind == VertexKind::removed || twin.cell == delaunay::kNoCell) continue;
    return w.guard->acquire(twin.cell) ? twin.cell : delaunay::kNoCell;
  }
  *none = true;
  return delaunay::kNoCell;
}

Outcome Operation::insert_copies_claimed(Worker& w, const Point4& point, VertexKind kind,
                                         CellId hint, Rule rule, const Point4* sample,
                                         double clearance) {
  if (!state_.covering.trusted(point)) return Outcome::skipped;
  check_budget(point);
  const auto& st = state_.tri.store();
  const double period = state_.covering.period().length;
  const std::array<Point4, 3> copies = state_.covering.copies(point);
  const double hint_time = PeriodicCovering::anchor(state_.tri, hint);
  // Each copy's cavity, and for R5 the stars of the free vertices near it, claimed as one
  // operation's would be. The copies lie a period apart: their regions are far apart once the
  // mesh is finer than the covering's margin, and then committing them one after the other
  // gives what the sequential order gives (each cavity is the same before and after the
  // others' commits, since no pentatope it holds or borders changes).
  std::array<bool, 3> active{};
  std::array<std::size_t, 4> region_end{};
  w.region.clear();
  for (int s = 0; s < 3; ++s) {
    w.copy_near[s].clear();
    if (s == 0 || state_.covering.in_covering(copies[s])) {
      const int periods = static_cast<int>(std::lround((copies[s][3] - hint_time) / period));
      CellId start = hint;
      if (periods != 0) {
        bool none = false;
        start = twin_start(w, hint, periods, &none);
        if (none) return Outcome::exclusive;  // a pentatope with no translates (a box corner)
        if (start == delaunay::kNoCell) return Outcome::conflict;
      }
      const CellId located = state_.tri.locate(copies[s], start, *w.ws, w.guard);
      if (located == delaunay::kNoCell) return Outcome::conflict;
      bool present = false;
      if (!st.is_infinite(located))
        for (VertexId u : st.cell(located).v) present = present || st.point(u) == copies[s];
      if (!present) {
        delaunay::Cavity& cavity = w.copy_cavity[s];
        if (!state_.tri.find_cavity(copies[s], kProvisionalId, located, cavity, w.guard))
          return Outcome::conflict;
        w.region.insert(w.region.end(), cavity.cells.begin(), cavity.cells.end());
        if (rule == Rule::R5 &&
            !claim_free_vertices_near(w, copies[s], cavity, w.copy_near[s], &w.region))
          return Outcome::conflict;
        active[s] = true;
      }
    }
    region_end[s + 1] = w.region.size();
  }
  if (!regions_apart(w, region_end)) return Outcome::exclusive;
  // R5's removals reach the twins of the removed vertices in every sheet (remove_twins): a
  // copy past the covering's end removes nothing there itself. Their stars are claimed too.
  if (rule == Rule::R5)
    for (int s = 0; s < 3; ++s)
      for (VertexId u : w.copy_near[s])
        for (int periods : {-2, -1, 1, 2}) {
          Point4 p = st.point(u);
          p[3] += periods * period;
          VertexId t;
          {
            std::shared_lock lock(copies_mutex_);
            t = state_.covering.vertex_inserted_at(p);
          }
          if (t == delaunay::kNoVertex) continue;
          if (!w.guard->lock(t)) return Outcome::conflict;
          if (st.vertex(t).kind != VertexKind::free) continue;
          if (!state_.tri.incident_cells(t, w.star, w.guard)) return Outcome::conflict;
        }
  if (kind == VertexKind::feature) {
    // Another thread may have sampled ∂Ω nearby since the rule was decided (the middle copy's
    // sample is checked: the index holds every copy of each feature).
    std::unique_lock lock(state_.features_mutex);
    if (sample) {
      Point4 shifted = *sample;
      shifted[3] += copies[0][3] - point[3];
      if (state_.features.any_within(shifted, clearance < 0 ? state_.params.delta : clearance))
        return Outcome::conflict;
    }
    for (int s = 0; s < 3; ++s)
      if (active[s]) state_.features.add(copies[s]);
  }
  // Nothing can roll back from here on.
  // The copies' ids are consecutive, as on one thread: the symbolic tie-break between
  // cospherical points orders them by id, and the sheets are triangulated alike only where any
  // two vertices are in the same order as their translates. (Taken copy by copy, another
  // thread's vertex could fall between two copies: the ventricle's covering was then
  // triangulated differently in two sheets, and its glued mesh had a non-manifold vertex that
  // the middle sheet did not have.)
  std::array<Point4, 3> made;
  std::size_t count = 0;
  for (int s = 0; s < 3; ++s)
    if (active[s]) made[count++] = copies[s];
  VertexId next =
      state_.tri.new_vertices({made.data(), count}, kind, w.guard ? w.locks.owner() : 0);
  std::vector<VertexId> removed;
  for (int s = 0; s < 3; ++s) {
    if (!active[s]) continue;
    std::swap(w.ws->cavity, w.copy_cavity[s]);
    w.near.swap(w.copy_near[s]);
    commit_insertion(w, copies[s], kind, rule, next++);
    removed.insert(removed.end(), w.removed.begin(), w.removed.end());
  }
  if (rule == Rule::R5) remove_twins(w, removed);
  return active[0] ? Outcome::done : Outcome::skipped;
}

bool Operation::regions_apart(const Worker& w, const std::array<std::size_t, 4>& region_end) {
  // Two pentatopes that are one, or neighbors, share vertices, so their spans in t overlap:
  // regions whose spans in t do not overlap share no pentatope and border none of each other's.
  // (Where they do, early on, when the pentatopes are as long as the period, the operation
  // runs alone.)
  const auto& st = state_.tri.store();
  std::array<std::pair<double, double>, 3> span;
  for (int s = 0; s < 3; ++s) {
    span[s] = {INFINITY, -INFINITY};
    for (std::size_t i = region_end[s]; i < region_end[s + 1]; ++i)
      for (VertexId u : st.cell(w.region[i]).v) {
        if (u == kInfiniteVertex) return false;
        const double t = st.point(u)[3];
        span[s].first = std::min(span[s].first, t);
        span[s].second = std::max(span[s].second, t);
      }
  }
  for (int s = 0; s < 3; ++s)
    for (int o = s + 1; o < 3; ++o)
      if (span[s].first <= span[o].second && span[o].first <= span[s].second) return false;
  return true;
}

void Operation::remove_twins(Worker& w, const std::vector<VertexId>& removed) {
  // The point set must stay invariant under a shift by T within the covering, or the sheets'
  // triangulations differ where the covering is trusted. A copy of p past the covering's end
  // is not inserted, but the free vertices it would have removed can lie inside the covering.
  // (In a parallel phase their stars were claimed with the operation's, or it runs alone.)
  const auto& st = state_.tri.store();
  std::vector<CellId> created, live;
  for (VertexId u : removed)
    for (int periods : {-2, -1, 1, 2}) {
      VertexId t;
      {
        std::shared_lock lock(copies_mutex_);
        t = state_.covering.twin(state_.tri, u, periods);
      }
      if (t == delaunay::kNoVertex || st.vertex(t).kind != VertexKind::free) continue;
      created.clear();
      if (w.guard) {
        if (!w.guard->lock(t))
          throw std::logic_error("Refiner: a twin to remove was not claimed with its operation");
        const auto result = state_.tri.remove(t, &created, *w.ws, w.guard);
        if (result == delaunay::Triangulation::RemoveResult::conflict)
          throw std::logic_error("Refiner: a twin's star was not claimed with its operation");
        if (result != delaunay::Triangulation::RemoveResult::removed) continue;
      } else if (!state_.tri.remove(t, &created)) {
        continue;
      }
      w.removals[index_of(Rule::R5)].fetch_add(1, std::memory_order_relaxed);
      live.clear();
      for (CellId c : created)
        if (st.is_live(c)) live.push_back(c);
      admit(w, live);
    }
}

void Operation::check_budget(const Point4& point) const {
  if (state_.tri.number_of_vertices() >= state_.params.vertex_budget) {
    std::ostringstream s;
    s << "refinement needs more than the vertex budget of " << state_.params.vertex_budget
      << " vertices; raise vertex_budget or delta";
    throw BudgetExceeded(s.str());
  }
  for (double x : point)
    if (!std::isfinite(x)) throw std::logic_error("Refiner: non-finite point to insert");
}

Outcome Operation::insert_one(Worker& w, const Point4& point, VertexKind kind, CellId hint,
                              Rule rule, const Point4* sample, double clearance) {
  check_budget(point);
  const auto& st = state_.tri.store();
  if (!w.guard && (hint == delaunay::kNoCell || !st.is_live(hint))) hint = state_.tri.any_cell();
  // The steps of Triangulation::insert, with the checks of a concurrent operation between
  // them: every lock is taken before the first write, so a conflict leaves nothing behind.
  const CellId start = state_.tri.locate(point, hint, *w.ws, w.guard);
  if (start == delaunay::kNoCell) return Outcome::conflict;
  if (!st.is_infinite(start))
    for (VertexId u : st.cell(start).v)
      if (st.point(u) == point) return Outcome::skipped;
  // The cavity is found with an id newer than any; the real id, taken only once nothing can
  // roll back any more, is newer than every vertex of the claimed pentatopes too (their
  // vertices were committed before this thread claimed them), so every tie-break is the same.
  if (!state_.tri.find_cavity(point, kProvisionalId, start, w.ws->cavity, w.guard))
    return Outcome::conflict;
  if (rule == Rule::R5 && !claim_free_vertices_near(w, point)) return Outcome::conflict;
  if (kind == VertexKind::feature) {
    // Another thread may have sampled ∂Ω nearby since the rule was decided.
    std::unique_lock lock(state_.features_mutex);
    if (sample &&
        state_.features.any_within(*sample, clearance < 0 ? state_.params.delta : clearance))
      return Outcome::conflict;
    state_.features.add(point);
  }
  commit_insertion(w, point, kind, rule);
  return Outcome::done;
}

void Operation::commit_insertion(Worker& w, const Point4& point, VertexKind kind, Rule rule,
                                 VertexId v) {
  const auto& st = state_.tri.store();
  w.removed.clear();
  if (observer_) observer_->before_commit(w, rule == Rule::R5);
  if (v == delaunay::kNoVertex)
    v = state_.tri.new_vertex(point, kind, w.guard ? w.locks.owner() : 0);
  if (w.guard) w.locks.adopt(v);
  if (state_.covering.active()) {
    std::unique_lock lock(copies_mutex_, std::defer_lock);
    if (w.guard) lock.lock();  // other threads look twins up meanwhile
    state_.covering.add(v, point);
  }
  state_.tri.commit(w.ws->cavity, v, *w.ws);
  w.insertions[index_of(rule)].fetch_add(1, std::memory_order_relaxed);
  w.created.clear();
  if (rule == Rule::R5)
    for (VertexId u : w.near)
      if (state_.tri.remove(u, &w.created, *w.ws, w.guard) ==
          delaunay::Triangulation::RemoveResult::removed) {
        w.removals[index_of(Rule::R5)].fetch_add(1, std::memory_order_relaxed);
        w.removed.push_back(u);
      }
  // The new pentatopes: the star of the new vertex (what commit made, unless removals changed
  // it), and what filled removed vertices' holes (some of those may have died in a later
  // removal).
  // They are queued in the order commit made them, each once (the star's), or else sorted to
  // drop repeats. Sorting the star too cost 1.4 % of the hypersphere's time; the order only
  // picks which of equally checked meshes comes out (seeds 1-5, every row: 1 % fewer
  // pentatopes, 2 % less time).
  if (w.near.empty() || rule != Rule::R5) {
    w.fresh.assign(w.ws->created.begin(), w.ws->created.end());
  } else {
    state_.tri.incident_cells(v, w.fresh);
    for (CellId c : w.created)
      if (st.is_live(c)) w.fresh.push_back(c);
    std::sort(w.fresh.begin(), w.fresh.end());
    w.fresh.erase(std::unique(w.fresh.begin(), w.fresh.end()), w.fresh.end());
  }
  admit(w, w.fresh);
  if (observer_) {
    std::sort(w.fresh.begin(), w.fresh.end());  // the observer searches them
    observer_->after_commit(w);
  }
}

Outcome Operation::process(Worker& w, const Candidate& k) {
  if (w.guard)
    for (VertexId u : k.v)
      if (!w.locks.lock(u)) return Outcome::conflict;
  if (!state_.still_valid(k)) return Outcome::skipped;
  w.conflict = false;
  Decision d = rules_.classify(w, k.cell);
  if (w.conflict) return Outcome::conflict;
  if (d.rule == Rule::none) return Outcome::skipped;
  // The computed circumcenter of a nearly degenerate pentatope (five surface points on one
  // voxel plane, nearly co-spherical) can lie outside its exact circumsphere; a point placed
  // from it then leaves the pentatope in place. Its centroid is inside it, so in conflict.
  const VertexId next_id =
      w.guard ? kProvisionalId : static_cast<VertexId>(state_.tri.store().vertex_slots());
  if (d.kind == VertexKind::free && !state_.tri.in_conflict(k.cell, d.point, next_id))
    d.point = state_.centroid_of(k.cell);
  // In periodic time a free point beyond the trusted band (the circumcenter of a pentatope that
  // reaches a box corner) would not go in, and the pentatope would stay; its centroid lies
  // inside it, nearer the middle sheet.
  if (d.kind == VertexKind::free && !state_.covering.trusted(d.point))
    d.point = state_.centroid_of(k.cell);
  // The sizing bound's insertions count as R3's (both insert the circumcenter inside Ω).
  const Outcome outcome =
      insert(w, d.point, d.kind, k.cell, d.rule == Rule::sizing ? Rule::R3 : d.rule,
             d.rule == Rule::R1 ? &d.sample : nullptr);
  // A pentatope that survives its operation (not in conflict with a surface point) is
  // classified again; each retry follows an insertion, so the vertex budget bounds them.
  if (outcome == Outcome::done && state_.still_valid(k)) enqueue(w, k.cell);
  return outcome;
}

bool Operation::claim_free_vertices_near(Worker& w, const Point4& p) {
  return claim_free_vertices_near(w, p, w.ws->cavity, w.near, nullptr);
}

bool Operation::claim_free_vertices_near(Worker& w, const Point4& p, const delaunay::Cavity& cavity,
                                         std::vector<VertexId>& near, std::vector<CellId>* region) {
  // R5's second half: free vertices closer than Δ to the new surface point go, so that the
  // surface is not approached too closely from inside (feature and box vertices stay). The new
  // point's neighbors are exactly the vertices of its cavity. In a parallel phase their stars
  // are claimed now, before the insertion commits: every pentatope the removals then touch is
  // one of those or is made of claimed vertices, so the removals cannot meet a lock.
  const auto& st = state_.tri.store();
  near.clear();
  for (CellId c : cavity.cells)
    for (VertexId u : st.cell(c).v)
      if (u != kInfiniteVertex && st.vertex(u).kind == VertexKind::free &&
          distance(st.point(u), p) < state_.params.delta &&
          std::find(near.begin(), near.end(), u) == near.end())
        near.push_back(u);
  if (w.guard)
    for (VertexId u : near) {
      if (!state_.tri.incident_cells(u, w.star, w.guard)) return false;
      if (region) region->insert(region->end(), w.star.begin(), w.star.end());
    }
  return true;
}

}  // namespace mesh4d::refine
