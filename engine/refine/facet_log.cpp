#include "refine/facet_log.h"

#include <algorithm>
#include <tuple>

#include "delaunay/facet_key.h"

namespace mesh4d::refine {

using delaunay::CellId;
using mesh4d::VertexId;

FacetLog::FacetLog(const RefinementState& state, unsigned workers)
    : state_(state), logs_(std::max(workers, 1u)) {}

void FacetLog::clear() {
  for (Log& log : logs_) log.changes.clear();
}

void FacetLog::boundary_facets_of(CellId c, int delta, std::vector<DoomedFacet>& out) const {
  const auto& cell = state_.tri.store().cell(c);
  const domain::Label own = state_.output_label(c);
  for (int i = 0; i < 5; ++i) {
    const domain::Label other = state_.output_label(cell.n[i]);
    if (other == own) continue;
    out.push_back({c, cell.n[i], {delaunay::facet_key(cell.v, i), own, other, delta, c}});
  }
}

void FacetLog::before_commit(Worker& w, bool removes) {
  Log& log = logs_[w.index];
  // In a parallel phase this thread holds all these pentatopes and the vertices they share
  // with their neighbors: their labels are stable.
  log.doomed.clear();
  log.doomed_facets.clear();
  for (CellId c : w.ws->cavity.cells) log.doomed.emplace_back(c, delaunay::kNoVertex);
  if (removes)
    for (VertexId u : w.near) {
      state_.tri.incident_cells(u, w.star);
      for (CellId c : w.star) log.doomed.emplace_back(c, u);
    }
  std::sort(log.doomed.begin(), log.doomed.end());
  for (std::size_t i = 0; i < log.doomed.size(); ++i)
    if (i == 0 || log.doomed[i].first != log.doomed[i - 1].first)
      boundary_facets_of(log.doomed[i].first, -1, log.doomed_facets);
}

void FacetLog::after_commit(Worker& w) {
  Log& log = logs_[w.index];
  // Dead: the cavity, and the stars of the vertices that were removed (a failed removal leaves
  // its star). A facet between two dead pentatopes went once; one between two new ones came
  // once.
  std::size_t dead = 0;
  for (std::size_t i = 0; i < log.doomed.size(); ++i) {
    const auto [c, u] = log.doomed[i];
    const bool dies = u == delaunay::kNoVertex ||
                      std::find(w.removed.begin(), w.removed.end(), u) != w.removed.end();
    if (dies && (dead == 0 || log.doomed[dead - 1].first != c)) log.doomed[dead++] = log.doomed[i];
  }
  log.doomed.resize(dead);  // sorted by cell, each once
  const auto died = [&](CellId c) {
    const auto it =
        std::lower_bound(log.doomed.begin(), log.doomed.end(), std::pair<CellId, VertexId>{c, 0});
    return it != log.doomed.end() && it->first == c;
  };
  const std::size_t first_change = log.changes.size();
  for (const DoomedFacet& f : log.doomed_facets)
    if (died(f.cell) && !(died(f.other) && f.other < f.cell)) log.changes.push_back(f.change);
  log.doomed_facets.clear();
  for (CellId c : w.fresh) boundary_facets_of(c, +1, log.doomed_facets);
  for (const DoomedFacet& f : log.doomed_facets)
    if (!(f.other < f.cell && std::binary_search(w.fresh.begin(), w.fresh.end(), f.other)))
      log.changes.push_back(f.change);
  log.doomed_facets.clear();
  cancel_opposite_changes(log.changes, first_change);
}

void FacetLog::cancel_opposite_changes(std::vector<FacetChange>& changes, std::size_t first) {
  // A facet of the cavity's boundary went with its dead pentatope and came with the new one on
  // the same side: with the same labels, the two changes cancel. Dropped here, before each
  // costs up to eight updates of the pinch counts (37 % of the changes on Pat05 at the files'
  // spacing, 401k → 253k).
  const auto key = [](const FacetChange& f) { return std::tie(f.facet, f.a, f.b, f.delta); };
  std::sort(changes.begin() + static_cast<std::ptrdiff_t>(first), changes.end(),
            [&](const FacetChange& x, const FacetChange& y) { return key(x) < key(y); });
  std::size_t kept = first;
  for (std::size_t i = first; i < changes.size(); ++i) {
    if (i + 1 < changes.size() && changes[i].delta < 0 && changes[i + 1].delta > 0 &&
        changes[i].facet == changes[i + 1].facet && changes[i].a == changes[i + 1].a &&
        changes[i].b == changes[i + 1].b) {
      ++i;  // both go
      continue;
    }
    changes[kept++] = changes[i];
  }
  changes.resize(kept);
}

}  // namespace mesh4d::refine
