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
  // boundary facet; sorting groups each triangle's facets.
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
  std::sort(records.begin(), records.end(),
            [](const Record& a, const Record& b) { return a.key < b.key; });
  std::size_t pinches = 0;
  for (std::size_t i = 0, j; i < records.size(); i = j) {
    for (j = i; j < records.size() && records[j].key == records[i].key;) ++j;
    if (j - i <= 2) continue;
    ++pinches;
    if (!pinched) continue;
    pinched->emplace_back();
    for (std::size_t k = i; k < j; ++k)
      pinched->back().facets.emplace_back(records[k].cell, records[k].facet);
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
