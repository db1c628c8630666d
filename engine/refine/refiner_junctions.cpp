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
        slot.pinch = static_cast<std::uint32_t>(pinched->size());
      }
      (*pinched)[slot.pinch - 1].facets.emplace_back(r.cell, r.facet);
    }
  }
  return pinches;
}

std::size_t Refiner::repair_pinches(double min_spacing) {
  std::vector<PinchedTriangle> pinched;
  if (count_pinches(&pinched) == 0) return 0;
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
    if (features_.any_within(p, min_spacing)) continue;
    inserted += insert_and_admit(p, VertexKind::feature, hint, kR1);  // a dead hint is ignored
  }
  return inserted;
}

}  // namespace mesh4d::refine
