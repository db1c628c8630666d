#include "delaunay/checker.h"

#include <sstream>
#include <vector>

namespace mesh4d::delaunay {
namespace {

CheckResult fail(const std::string& what, CellId c) {
  std::ostringstream s;
  s << what << " (pentatope " << c << ")";
  return {false, s.str()};
}

}  // namespace

CheckResult check_triangulation(const Triangulation& t) {
  const PentatopeStore& st = t.store();
  if (t.dimension() < 4) return {};
  std::vector<char> seen(st.vertex_slots(), 0);
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c)) continue;
    const Pentatope& cell = st.cell(c);
    for (int i = 0; i < 5; ++i) {
      if (cell.v[i] >= st.vertex_slots()) return fail("vertex id out of range", c);
      if (st.vertex(cell.v[i]).kind == VertexKind::removed) return fail("removed vertex used", c);
      seen[cell.v[i]] = 1;
      for (int j = 0; j < i; ++j)
        if (cell.v[i] == cell.v[j]) return fail("repeated vertex", c);
    }
    for (int i = 0; i < 5; ++i) {
      const CellId d = cell.n[i];
      if (d == kNoCell || !st.is_live(d)) return fail("missing or dead neighbor", c);
      const int back = st.neighbor_index(d, c);
      if (back < 0) return fail("neighbor does not point back", c);
      // d must hold every vertex of c but v[i], and its far vertex d.v[back] must not be in c.
      for (int k = 0; k < 5; ++k)
        if (k != i && st.index_of(d, cell.v[k]) < 0) return fail("neighbor shares no facet", c);
      if (st.index_of(c, st.cell(d).v[back]) >= 0) return fail("neighbor is a copy", c);
    }
    const int inf = st.index_of(c, kInfiniteVertex);
    if (inf < 0) {
      if (t.orient_with(c, 0, st.point(cell.v[0])) <= 0) return fail("not positively oriented", c);
    } else {
      const CellId inner = cell.n[inf];
      if (st.is_infinite(inner)) return fail("hull facet between two infinite pentatopes", c);
      const VertexId far = st.cell(inner).v[st.neighbor_index(inner, c)];
      if (t.orient_with(c, inf, st.point(far)) >= 0) return fail("hull facet wrongly oriented", c);
    }
    // Local Delaunay: the far vertex of each finite-side neighbor is outside c's circumsphere.
    for (int i = 0; i < 5; ++i) {
      const CellId d = cell.n[i];
      const VertexId far = st.cell(d).v[st.neighbor_index(d, c)];
      if (far == kInfiniteVertex) continue;
      if (inf >= 0 && i == inf) continue;  // checked above as the hull facet's orientation
      if (t.in_conflict(c, st.point(far), far)) return fail("not Delaunay across a facet", c);
    }
  }
  std::size_t vertices = 0;
  for (VertexId v = 1; v < st.vertex_slots(); ++v) {
    const Vertex& vx = st.vertex(v);
    if (vx.kind == VertexKind::removed) continue;
    if (!seen[v]) {
      std::ostringstream s;
      s << "vertex " << v << " is in no pentatope";
      return {false, s.str()};
    }
    if (!st.is_live(vx.cell) || st.index_of(vx.cell, v) < 0) {
      std::ostringstream s;
      s << "vertex " << v << " has a stale incident pentatope";
      return {false, s.str()};
    }
    ++vertices;
  }
  if (vertices != t.number_of_vertices()) return {false, "vertex count mismatch"};
  return {};
}

}  // namespace mesh4d::delaunay
