#include "refine/manifold_sampling.h"

#include <algorithm>
#include <iterator>

#include "refine/manifold_relabeling.h"

namespace mesh4d::refine {

using delaunay::CellId;
using mesh4d::VertexId;

namespace {

// On the patients at δ 5 the count falls to none within twelve rounds. At the paper's spacing
// (6 mm between slices) Pat05's last pair took 20, with the halvings below. A round costs a few
// hundredths of a second (the stars around the new points, not the whole boundary).
constexpr int kRounds = 24;
// How close (in Δ) a sample may come to a feature vertex: the pinch repair's finer spacing. When
// a round of every sample inserts nothing (each lies that close to a feature vertex), it halves,
// up to three times (to Δ/32).
constexpr double kSpacing = 0.25;
constexpr int kSpacingHalvings = 3;

// Every vertex whose star an operation changed: those of the pentatopes it made (an insertion's
// cavity and a removal's hole are filled by pentatopes on all of their boundary's vertices).
class StarLog final : public FacetObserver {
 public:
  explicit StarLog(const RefinementState& state, unsigned workers)
      : state_(state), logs_(workers) {}
  void before_commit(Worker&, bool) override {}
  void after_commit(Worker& w) override {
    auto& log = logs_[w.index];
    for (CellId c : w.fresh)
      for (VertexId v : state_.tri.store().cell(c).v)
        if (v != delaunay::kInfiniteVertex) log.push_back(v);
  }
  // Every worker's vertices, sorted, each once; the logs are emptied.
  std::vector<VertexId> take() {
    std::vector<VertexId> all;
    for (auto& log : logs_) all.insert(all.end(), log.begin(), log.end()), log.clear();
    std::sort(all.begin(), all.end());
    all.erase(std::unique(all.begin(), all.end()), all.end());
    return all;
  }

 private:
  const RefinementState& state_;
  std::vector<std::vector<VertexId>> logs_;
};

}  // namespace

void ManifoldSampling::samples_at(const NonManifoldVertex& f, double spacing, bool every,
                                  std::vector<RepairPoint>& out) const {
  const auto& st = state_.tri.store();
  std::vector<CellId> star;
  state_.tri.incident_cells(f.vertex, star);
  std::vector<std::pair<double, RepairPoint>> found;  // (-distance to v, sample)
  const auto add = [&](const Point4& z, CellId c) {
    if (state_.feature_within(z, spacing)) return;
    found.push_back({-distance(z, st.point(f.vertex)), RepairPoint{z, state_.candidate(c)}});
  };
  std::vector<std::pair<CellId, CellId>> no_crossing;  // restricted facets, as (inside, outside)
  for (CellId c : star) {
    if (state_.output_label(c) != f.label) continue;
    const auto& cell = st.cell(c);
    for (int i = 0; i < 5; ++i) {
      const CellId n = cell.n[i];
      // A restricted facet through v: opposite another vertex, with another label across.
      if (cell.v[i] == f.vertex || state_.output_label(n) == f.label) continue;
      if (!state_.info[c].finite || !state_.info[n].finite) continue;
      const auto z = state_.oracle.first_crossing(state_.info[c].center, state_.info[n].center);
      if (z)
        add(z->point, c);
      else
        no_crossing.push_back({c, n});
    }
  }
  // Where a relabeling moved one side of a facet, the label function may not change between
  // the circumcenters. When no other facet gives a sample, ∂Ω's points nearest those facets'
  // Voronoi edges' middles are the samples (a closest-point search each, so only then).
  if (found.empty())
    for (const auto& [c, n] : no_crossing) {
      Point4 middle;
      for (int k = 0; k < 4; ++k)
        middle[k] = 0.5 * (state_.info[c].center[k] + state_.info[n].center[k]);
      const domain::SurfacePoint near = state_.oracle.closest_surface_point(middle);
      if (near.inner != near.outer) add(near.point, c);
    }
  std::stable_sort(found.begin(), found.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (const auto& [d, r] : found) {
    out.push_back(r);
    if (!every) break;
  }
}

ManifoldSampling::Outcome ManifoldSampling::run(std::vector<NonManifoldVertex> failing,
                                                const Drain& drain, const Insert& insert,
                                                std::vector<RepairPoint> extra) {
  Outcome outcome;
  double spacing = kSpacing * state_.params.delta;
  int halvings = 0;
  StarLog log(state_, workers_);
  std::size_t last = failing.size() + 1;
  for (; outcome.rounds < kRounds && (!failing.empty() || !extra.empty()); ++outcome.rounds) {
    // One sample per failing pair (the farthest: the facet the rules left coarsest), or all of
    // them when the last round did not help.
    const bool every = failing.size() >= last;
    last = failing.size();
    std::vector<RepairPoint> points = std::move(extra);
    extra.clear();
    for (const NonManifoldVertex& f : failing) samples_at(f, spacing, every, points);
    operation_.set_observer(&log);
    const std::size_t inserted = insert(points, spacing);
    if (inserted > 0) drain();
    operation_.set_observer(nullptr);
    outcome.points += inserted;
    if (inserted == 0 && every) {
      if (halvings++ == kSpacingHalvings) break;
      spacing /= 2;
      continue;
    }
    // The links that can have changed: the new pentatopes' vertices, and the failing ones.
    std::vector<VertexId> around = log.take();
    for (const NonManifoldVertex& f : failing) around.push_back(f.vertex);
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    ManifoldRelabeling relabeling(state_, scan_);
    ManifoldRelabeling::Outcome relabeled = relabeling.run(&around);
    outcome.moved += relabeled.moved;
    failing = std::move(relabeled.failing);
  }
  outcome.failing = std::move(failing);
  return outcome;
}

}  // namespace mesh4d::refine
