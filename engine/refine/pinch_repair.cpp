#include "refine/pinch_repair.h"

#include <algorithm>
#include <stdexcept>
#include <tuple>

#include "refine/repair_policy.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using mesh4d::VertexId;

namespace {

// Each round is followed by the rules. Since the manifold relabeling closes what the rounds
// leave, only the first few pay (docs/performance.md, "Pinch repair rounds"): on the ten
// patient rows, 3 rounds instead of 40 take 0.6–0.7 of the time with as few or fewer failing
// links left, for 0.1–1.1 % less 4-volume.
constexpr int kRepairRounds = 3;
// Pinched triangles per thread, at least, when their repair points are found on the job's
// threads.
constexpr std::size_t kTrianglesPerThread = 32;

}  // namespace

PinchRepair::PinchRepair(RefinementState& state, const PinchScan& scan, Operation& operation)
    : state_(state),
      scan_(scan),
      operation_(operation),
      log_(state, std::max(state.params.threads, 1u)) {}

std::vector<PinchedTriangle> PinchRepair::run(const Drain& drain, const Insert& insert) {
  // Points closer than half of Δ to a sampled one are allowed only when nothing else is left
  // or the count stalls, down to Δ/16, and a finer level that makes the count grow ends the
  // repair (RepairPolicy). (Starting at a quarter of Δ, the short edges of the points squeezed
  // in set off the radius-edge rule around them: on the ventricle the repair then doubled the
  // mesh after the rules, for the same fidelity.)
  const double delta = state_.params.delta;
  double min_spacing = 0.5 * delta;
  bool counted_since = false;  // no insertion since the last count
  RepairPolicy policy;
  for (int round = 0; round < kRepairRounds && min_spacing >= delta / 16;) {
    // The count a full scan gives (the first one is a scan; later ones follow the facets that
    // the round's insertions changed, which a test checks against scans).
    const std::size_t pinches = count();
    counted_since = true;
    const RepairPolicy::Next next = policy.observe(pinches);
    if (next == RepairPolicy::Next::stop) break;
    if (next == RepairPolicy::Next::repair && repair(min_spacing, insert) > 0) {
      counted_since = false;
      ++round;
      drain();
      continue;
    }
    min_spacing /= 2;
    policy.finer();
  }
  // After the last round's rules, one more count from the facets they changed: the relabeling
  // needs the pinches, and a full scan of its own cost it a pass over every boundary facet.
  if (!counted_since) count();
  operation_.set_observer(nullptr);
  logging_ = false;
  log_.clear();
  counts_.clear();
  return std::move(known_);
}

std::size_t PinchRepair::count_from_facet_changes(std::vector<PinchedTriangle>* pinched) {
  for (unsigned w = 0; w < log_.workers(); ++w)
    for (const FacetChange& f : log_.changes(w))
      for (const domain::Label l : {f.a, f.b}) {
        if (!state_.output_region(l)) continue;
        for (int skip = 0; skip < 4; ++skip) {
          PinchKey key{l, 0, 0, 0};
          for (int k = 0, m = 1; k < 4; ++k)
            if (k != skip) key[m++] = f.facet[k];
          // As the full count: in periodic time the middle sheet's triangles only.
          if (!scan_.counts_triangle({key[1], key[2], key[3]})) continue;
          counts_.add(key, f.delta, f.cell);
        }
      }
  log_.clear();
  // Each pinched triangle walked once, from a pentatope through it: one of its facets in the
  // last count (known_, sorted by triangle), or the one whose facet pushed a count
  // above two, or else one of its first vertex's star (a star per triangle was 4 % of the run).
  auto keys = counts_.pinched();
  std::sort(keys.begin(), keys.end(), [](const PinchCounts::Pinch& a, const PinchCounts::Pinch& b) {
    return std::tie(a.key[1], a.key[2], a.key[3], a.key[0]) <
           std::tie(b.key[1], b.key[2], b.key[3], b.key[0]);
  });
  const auto& st = state_.tri.store();
  std::vector<CellId> star;
  const std::size_t before = pinched->size();
  for (std::size_t i = 0; i < keys.size(); ++i) {
    const std::array<VertexId, 3> t{keys[i].key[1], keys[i].key[2], keys[i].key[3]};
    const auto same_t = [&](std::size_t j) {
      return std::equal(t.begin(), t.end(), keys[j].key.begin() + 1);
    };
    if (i > 0 && same_t(i - 1)) continue;
    const auto through = [&](CellId c) {
      if (!st.is_live(c)) return false;
      int found = 0;
      for (VertexId v : st.cell(c).v) found += v == t[0] || v == t[1] || v == t[2];
      return found == 3;
    };
    CellId start = delaunay::kNoCell;
    auto known = std::lower_bound(
        known_.begin(), known_.end(), t,
        [](const PinchedTriangle& p, const std::array<VertexId, 3>& x) { return p.triangle < x; });
    for (; known != known_.end() && known->triangle == t && start == delaunay::kNoCell; ++known)
      for (const auto& [c, facet] : known->facets)
        if (through(c)) {
          start = c;
          break;
        }
    for (std::size_t j = i; j < keys.size() && same_t(j) && start == delaunay::kNoCell; ++j)
      if (through(keys[j].cell)) start = keys[j].cell;
    if (start == delaunay::kNoCell) {
      state_.tri.incident_cells(t[0], star);
      for (CellId c : star)
        if (through(c)) {
          start = c;
          break;
        }
    }
    if (start != delaunay::kNoCell) scan_.pinches_at(start, t, pinched);
  }
  return pinched->size() - before;
}

std::size_t PinchRepair::count() {
  std::vector<PinchedTriangle> pinched;
  // The first count scans everything; later ones follow the facet changes.
  const std::size_t found =
      logging_ ? count_from_facet_changes(&pinched) : scan_.count(&pinched, &counts_, true);
  if (logging_) ++counts_from_changes_;
  if (check_counts_ && logging_) {
    ++counts_checked_;
    std::vector<PinchedTriangle> full;
    PinchCounts counts;
    scan_.count(&full, &counts);
    if (!(counts == counts_))
      throw std::logic_error(
          "PinchRepair: the triangles' counts from facet changes differ from a full count");
    scan_.sort_canonically(full);
    scan_.sort_canonically(pinched);
    const auto same = [](const PinchedTriangle& a, const PinchedTriangle& b) {
      return a.triangle == b.triangle && a.facets == b.facets;
    };
    if (!std::equal(pinched.begin(), pinched.end(), full.begin(), full.end(), same))
      throw std::logic_error(
          "PinchRepair: the pinches counted from facet changes differ from a full count");
  }
  if (!logging_) operation_.set_observer(&log_);
  logging_ = true;
  // In canonical order: the repair's points go in in this order, however the list was found.
  scan_.sort_canonically(pinched);
  known_ = std::move(pinched);
  return found;
}

bool PinchRepair::repair_point_of(const PinchedTriangle& t, Point4* point, CellId* hint) const {
  // The surface center of its largest restricted facet (the one the rules left coarsest).
  const auto& st = state_.tri.store();
  double largest = -1;
  for (const auto& [c, i] : t.facets) {
    const CellId n = st.cell(c).n[i];
    if (!state_.info[n].finite) continue;
    const auto z = state_.oracle.first_crossing(state_.info[c].center, state_.info[n].center);
    if (!z) continue;
    const Point4& v = st.point(st.cell(c).v[(i + 1) % 5]);
    double r2 = 0;
    for (int k = 0; k < 4; ++k) r2 += (z->point[k] - v[k]) * (z->point[k] - v[k]);
    if (r2 > largest) largest = r2, *point = z->point, *hint = c;
  }
  return largest >= 0;
}

std::size_t PinchRepair::repair(double min_spacing, const Insert& insert) {
  // A point per pinched triangle; all are found before any goes in, as cells die with
  // insertions. A point near a sampled one is refused (the insertion asks again, as points of
  // this round go in first). In periodic time the middle sheet's pinches only: a point goes in
  // with its copies, which repair the other sheets' copies of the pinch. (Read only: on the job's
  // threads, each a contiguous share of the triangles, joined in order.)
  const unsigned parts =
      support::parts_for(known_.size(), kTrianglesPerThread, working_threads(state_.params));
  std::vector<std::vector<RepairPoint>> found(parts);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(known_.size(), part, parts);
    for (std::size_t i = begin; i < end; ++i) {
      Point4 point;
      CellId hint = delaunay::kNoCell;
      if (!scan_.counted(known_[i]) || !repair_point_of(known_[i], &point, &hint) ||
          state_.feature_within(point, min_spacing))
        continue;
      found[part].push_back(RepairPoint{point, state_.candidate(hint)});
    }
  });
  std::vector<RepairPoint> points;
  for (const auto& f : found) points.insert(points.end(), f.begin(), f.end());
  return insert(points, min_spacing);
}

}  // namespace mesh4d::refine
