#include "refine/periodic_covering.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::kInfiniteVertex;
using delaunay::kNoVertex;

std::size_t PeriodicCovering::PointHash::operator()(const Point4& p) const {
  std::size_t h = 0;
  for (double x : p) {
    // −0.0 == 0.0: both must hash alike (a time wrapped to −0.0 is looked up as 0.0).
    const double value = x == 0 ? 0.0 : x;
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    h = (h ^ bits) * 0x9E3779B97F4A7C15ull;
  }
  return h ^ (h >> 29);
}

double PeriodicCovering::anchor(const delaunay::Triangulation& tri, CellId c) {
  const auto& st = tri.store();
  double lowest = INFINITY;
  for (mesh4d::VertexId v : st.cell(c).v)
    if (v != kInfiniteVertex) lowest = std::min(lowest, st.point(v)[3]);
  return lowest;
}

bool PeriodicCovering::rules_apply(const delaunay::Triangulation& tri, CellId c) const {
  if (representative(tri, c)) return true;
  const auto& st = tri.store();
  for (mesh4d::VertexId v : st.cell(c).v)
    if (v != kInfiniteVertex && st.vertex(v).kind == delaunay::VertexKind::box) return true;
  return false;
}

std::array<Point4, 3> PeriodicCovering::copies(const Point4& p) const {
  Point4 middle = p;
  middle[3] = period_.wrap(p[3]);
  std::array<Point4, 3> out{middle, middle, middle};
  out[1][3] -= period_.length;  // exact: both on the grid of kTimeQuantum
  out[2][3] += period_.length;
  return out;
}

mesh4d::VertexId PeriodicCovering::vertex_inserted_at(const Point4& p) const {
  const auto it = where_.find(p);
  return it == where_.end() ? kNoVertex : it->second;
}

mesh4d::VertexId PeriodicCovering::vertex_at(const delaunay::Triangulation& tri,
                                             const Point4& p) const {
  const mesh4d::VertexId v = vertex_inserted_at(p);
  // Removed vertices stay in the map: their ids are never handed out again.
  if (v == kNoVertex || tri.store().vertex(v).kind == delaunay::VertexKind::removed)
    return kNoVertex;
  return v;
}

mesh4d::VertexId PeriodicCovering::twin(const delaunay::Triangulation& tri, mesh4d::VertexId v,
                                        int periods) const {
  if (v == kInfiniteVertex) return kNoVertex;
  Point4 p = tri.store().point(v);
  p[3] += periods * period_.length;
  return vertex_at(tri, p);
}

void PeriodicCovering::twin_cells(const delaunay::Triangulation& tri, CellId c,
                                  std::vector<CellId>& out) const {
  out.clear();
  const auto& st = tri.store();
  const double a = anchor(tri, c);
  const int sheet = static_cast<int>(std::floor((a - period_.start) / period_.length));
  std::vector<CellId> star;
  for (int other = -1; other <= 1; ++other) {
    if (other == sheet) continue;
    std::array<mesh4d::VertexId, 5> twins;
    bool all = true;
    for (int i = 0; i < 5 && all; ++i) {
      twins[i] = twin(tri, st.cell(c).v[i], other - sheet);
      all = twins[i] != kNoVertex;
    }
    if (!all) continue;
    std::sort(twins.begin(), twins.end());
    tri.incident_cells(twins[0], star);
    for (CellId s : star) {
      std::array<mesh4d::VertexId, 5> v;
      std::copy(std::begin(st.cell(s).v), std::end(st.cell(s).v), v.begin());
      std::sort(v.begin(), v.end());
      if (v == twins) {
        out.push_back(s);
        break;
      }
    }
  }
}

}  // namespace mesh4d::refine
