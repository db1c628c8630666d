// Pinch repair: where three labels meet (the ventricle's pool, wall and background), the
// paper's rules, proven for one label, can leave a label's region boundary pinched: a triangle
// in four or more of the region's boundary tetrahedra. The restricted facets around such a
// triangle are sampled at their surface centers (points of ∂Ω on their Voronoi edges, as R5
// uses), which splits them, and the rules run again.
#include <algorithm>
#include <array>

#include "delaunay/spatial_sort.h"
#include "domain/junctions.h"
#include "refine/refiner.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;

void Refiner::insert_junctions() {
  if (params_.junction_spacing <= 0) return;
  const double spacing = params_.junction_spacing * params_.delta;
  const auto junctions = domain::sample_junctions(
      oracle_, [&](const Point4& p) { return !features_.any_within(p, spacing); },
      [&](const Point4& p) { features_.add(p); });
  std::vector<Point4> points;
  points.reserve(junctions.size());
  for (const auto& j : junctions) points.push_back(j.point);
  // Before any rule runs, straight into the triangulation: the first admit() sees every cell.
  for (std::size_t i : delaunay::spatial_order(points)) tri_.insert(points[i], VertexKind::feature);
}

std::size_t Refiner::count_pinches(std::vector<PinchedTriangle>* pinched) const {
  // Records (region label, sorted triangle, facet) for every triangle of every region's
  // boundary facet.
  struct Record {
    std::array<std::uint32_t, 4> key;  // label, then the triangle's vertices
    CellId cell;
    int facet;
  };
  const auto& st = tri_.store();
  std::vector<Record> records;
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c) || !info_[c].finite || info_[c].label == 0) continue;
    const auto& cell = st.cell(c);
    for (int i = 0; i < 5; ++i) {
      const CellId n = cell.n[i];
      const domain::Label other = st.is_infinite(n) || !info_[n].finite ? 0 : info_[n].label;
      if (other == info_[c].label) continue;
      std::array<std::uint32_t, 4> facet;
      for (int k = 0, m = 0; k < 5; ++k)
        if (k != i) facet[m++] = cell.v[k];
      std::sort(facet.begin(), facet.end());
      for (int skip = 0; skip < 4; ++skip) {
        Record r{{info_[c].label, 0, 0, 0}, c, i};
        for (int k = 0, m = 1; k < 4; ++k)
          if (k != skip) r.key[m++] = facet[k];
        records.push_back(r);
      }
    }
  }
  // Count each triangle's facets in an open-addressing table (a sort of all records cost a
  // fifth of the ventricle's refinement, as the repair recounts after every round).
  struct Slot {
    std::array<std::uint32_t, 4> key;
    std::uint32_t count = 0;
    std::uint32_t pinch = 0;  // 1 + index in *pinched, once listed
  };
  std::size_t size = 16;
  while (size < 2 * records.size()) size *= 2;
  std::vector<Slot> table(size);
  const auto slot_of = [&](const std::array<std::uint32_t, 4>& key) -> Slot& {
    std::uint64_t h = (std::uint64_t(key[0]) << 32 | key[1]) * 0x9E3779B97F4A7C15ull;
    h ^= (std::uint64_t(key[2]) << 32 | key[3]) * 0xC2B2AE3D27D4EB4Full;
    h ^= h >> 29;
    for (std::size_t i = h & (size - 1);; i = (i + 1) & (size - 1))
      if (table[i].count == 0 || table[i].key == key) return table[i];
  };
  std::size_t pinches = 0;
  for (const Record& r : records) {
    Slot& slot = slot_of(r.key);
    slot.key = r.key;
    if (++slot.count == 3) ++pinches;
  }
  if (pinched && pinches) {
    for (const Record& r : records) {
      Slot& slot = slot_of(r.key);
      if (slot.count <= 2) continue;
      if (slot.pinch == 0) {
        pinched->emplace_back();
        pinched->back().triangle = {r.key[1], r.key[2], r.key[3]};
        slot.pinch = static_cast<std::uint32_t>(pinched->size());
      }
      (*pinched)[slot.pinch - 1].facets.emplace_back(r.cell, r.facet);
    }
  }
  return pinches;
}

void Refiner::link_cycle(CellId start, const std::array<VertexId, 3>& t, std::vector<CellId>& cycle,
                         std::vector<int>& crossed) const {
  // The link of a triangle in a 4D triangulation is a circle: each pentatope around it has two
  // facets through it (opposite its two other vertices), one shared with each neighbor on the
  // cycle. Crossing, each time, the facet opposite the other vertex shared with the previous
  // pentatope walks the cycle.
  const auto& st = tri_.store();
  const auto in_t = [&](VertexId v) { return v == t[0] || v == t[1] || v == t[2]; };
  cycle.clear();
  crossed.clear();
  CellId cur = start;
  VertexId cross = delaunay::kNoVertex;
  for (int k = 0; k < 5; ++k)
    if (!in_t(st.cell(cur).v[k])) {
      cross = st.cell(cur).v[k];
      break;
    }
  for (int guard = 0; guard < 100000; ++guard) {
    const auto& cell = st.cell(cur);
    int i = 0, other = -1;
    for (int k = 0; k < 5; ++k) {
      if (cell.v[k] == cross)
        i = k;
      else if (!in_t(cell.v[k]))
        other = k;
    }
    cycle.push_back(cur);
    crossed.push_back(i);
    cross = cell.v[other];
    cur = cell.n[i];
    if (cur == start) break;
  }
}

void Refiner::pinches_at(CellId start, const std::array<VertexId, 3>& t,
                         std::vector<PinchedTriangle>* pinched) const {
  // A region's boundary facets at t are its label changes along the cycle around t.
  const auto& st = tri_.store();
  std::vector<CellId> cycle;
  std::vector<int> crossed;  // facet of cycle[i] shared with cycle[i + 1]
  link_cycle(start, t, cycle, crossed);
  const auto label_of = [&](CellId c) { return output_label(c); };
  std::vector<domain::Label> labels;
  for (CellId c : cycle)
    if (const domain::Label l = label_of(c);
        l != 0 && std::find(labels.begin(), labels.end(), l) == labels.end())
      labels.push_back(l);
  const std::size_t n = cycle.size();
  for (const domain::Label l : labels) {
    PinchedTriangle p{t, {}};
    for (std::size_t i = 0; i < n; ++i) {
      const CellId a = cycle[i], b = cycle[(i + 1) % n];
      if ((label_of(a) == l) == (label_of(b) == l)) continue;
      if (label_of(a) == l) {
        p.facets.emplace_back(a, crossed[i]);
      } else {
        int back = 0;
        while (st.cell(b).n[back] != a) ++back;
        p.facets.emplace_back(b, back);
      }
    }
    if (p.facets.size() > 2) pinched->push_back(std::move(p));
  }
}

std::size_t Refiner::recount_pinches(std::vector<PinchedTriangle>* pinched) {
  // Candidate triangles with a live pentatope through each.
  const auto& st = tri_.store();
  std::vector<std::pair<std::array<VertexId, 3>, CellId>> candidates;
  for (CellId c : touched_) {
    if (!st.is_live(c) || st.is_infinite(c)) continue;
    const auto& cell = st.cell(c);
    const domain::Label own = info_[c].finite ? info_[c].label : 0;
    for (int i = 0; i < 5; ++i) {
      const CellId nb = cell.n[i];
      const domain::Label other = st.is_infinite(nb) || !info_[nb].finite ? 0 : info_[nb].label;
      if (other == own) continue;
      std::array<VertexId, 4> facet;
      for (int k = 0, m = 0; k < 5; ++k)
        if (k != i) facet[m++] = cell.v[k];
      std::sort(facet.begin(), facet.end());
      for (int skip = 0; skip < 4; ++skip) {
        std::array<VertexId, 3> t;
        for (int k = 0, m = 0; k < 4; ++k)
          if (k != skip) t[m++] = facet[k];
        candidates.emplace_back(t, c);
      }
    }
  }
  std::vector<CellId> star;
  for (const PinchedTriangle& p : known_pinches_) {
    // A pentatope of the old pinch may be gone; any live one through the triangle will do.
    CellId through = delaunay::kNoCell;
    for (const auto& [c, i] : p.facets)
      if (st.is_live(c) && !st.is_infinite(c)) {
        int found = 0;
        for (VertexId v : st.cell(c).v)
          found += v == p.triangle[0] || v == p.triangle[1] || v == p.triangle[2];
        if (found == 3) {
          through = c;
          break;
        }
      }
    bool alive = true;
    for (VertexId v : p.triangle) alive = alive && st.vertex(v).kind != VertexKind::removed;
    if (through == delaunay::kNoCell && alive) {
      tri_.incident_cells(p.triangle[0], star);
      for (CellId c : star) {
        int found = 0;
        for (VertexId v : st.cell(c).v) found += v == p.triangle[1] || v == p.triangle[2];
        if (found == 2) {
          through = c;
          break;
        }
      }
    }
    if (through != delaunay::kNoCell) candidates.emplace_back(p.triangle, through);
  }
  std::sort(candidates.begin(), candidates.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  const std::size_t before = pinched->size();
  for (std::size_t i = 0; i < candidates.size(); ++i) {
    if (i > 0 && candidates[i].first == candidates[i - 1].first) continue;
    pinches_at(candidates[i].second, candidates[i].first, pinched);
  }
  return pinched->size() - before;
}

std::size_t Refiner::repair_pinches(double min_spacing) {
  std::vector<PinchedTriangle> pinched;
  // The first count scans everything; later ones look only where pentatopes changed.
  const std::size_t found = tracking_ ? recount_pinches(&pinched) : count_pinches(&pinched);
  tracking_ = true;
  touched_.clear();
  known_pinches_ = pinched;
  if (found == 0) return 0;
  // Per pinched triangle, the surface center of its largest restricted facet (the one the
  // rules left coarsest); all are found before any goes in, as cells die with insertions.
  std::vector<std::pair<Point4, CellId>> points;
  const auto& st = tri_.store();
  for (const PinchedTriangle& t : pinched) {
    double largest = -1;
    Point4 best;
    CellId hint = delaunay::kNoCell;
    for (const auto& [c, i] : t.facets) {
      const CellId n = st.cell(c).n[i];
      if (st.is_infinite(n) || !info_[n].finite) continue;
      const auto z = oracle_.first_crossing(info_[c].center, info_[n].center);
      if (!z) continue;
      const Point4& v = st.point(st.cell(c).v[(i + 1) % 5]);
      double r2 = 0;
      for (int k = 0; k < 4; ++k) r2 += (z->point[k] - v[k]) * (z->point[k] - v[k]);
      if (r2 > largest) largest = r2, best = z->point, hint = c;
    }
    if (largest >= 0) points.emplace_back(best, hint);
  }
  std::size_t inserted = 0;
  for (const auto& [p, hint] : points) {
    // A point already sampled nearby would make a short edge and change little.
    if (feature_within(p, min_spacing)) continue;
    // (A dead hint is ignored.)
    inserted += insert_and_admit(*workers_[0], p, VertexKind::feature, hint, kR1) == Outcome::done;
  }
  return inserted;
}

}  // namespace mesh4d::refine
