// Point location and Bowyer–Watson insertion.
#include "delaunay/triangulation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

#include "delaunay/insphere_batch.h"
#include "delaunay/predicate_kernels.h"
#include "delaunay/predicates.h"
#include "delaunay/spatial_sort.h"

namespace mesh4d::delaunay {

namespace {

// kRidgeSlots[a][b]: the three slots of a pentatope other than a and b (a ≠ b), in increasing
// order: the ridge left when the vertices in slots a and b are taken away.
constexpr auto kRidgeSlots = [] {
  std::array<std::array<std::array<int, 3>, 5>, 5> table{};
  for (int a = 0; a < 5; ++a)
    for (int b = 0; b < 5; ++b) {
      int m = 0;
      for (int i = 0; i < 5 && m < 3; ++i)
        if (i != a && i != b) table[a][b][m++] = i;
    }
  return table;
}();

}  // namespace

Triangulation::Triangulation(unsigned block_shift)
    : store_(block_shift), own_(&store_.own_allocator()) {}

void Triangulation::reset() {
  store_.reset();
  dimension_ = -1;
  vertex_count_ = 0;
  any_cell_ = kNoCell;
  pending_.clear();
  // A reset triangulation walks as a new one: the vertex removal reuses one per thread, and
  // the order of its pentatopes decides the refinement order after it (same seed, same mesh).
  own_.walk_rng = Workspace::kWalkSeed;
}

std::size_t Triangulation::number_of_finite_cells() const {
  std::size_t n = 0;
  for (CellId c = 0; c < store_.cell_slots(); ++c)
    if (store_.is_live(c) && !store_.is_infinite(c)) ++n;
  return n;
}

void Triangulation::clear_stamps() {
  for (CellId c = 0; c < store_.cell_slots(); ++c) store_.cell(c).mark = 0;
  stamp_.store(0, std::memory_order_relaxed);
}

std::uint32_t Triangulation::next_stamp() {
  // Stamps come in pairs (in conflict, rejected) and only grow, so an old stamp never matches.
  // On wrap-around every stamp is cleared once (single-threaded: a parallel phase stops before,
  // see stamps_running_low()).
  std::uint32_t stamp = stamp_.fetch_add(2, std::memory_order_relaxed) + 2;
  if (stamp >= kStampLimit) {
    clear_stamps();
    stamp = stamp_.fetch_add(2, std::memory_order_relaxed) + 2;
  }
  return stamp;
}

VertexId Triangulation::new_vertex(const Point4& p, VertexKind kind, std::uint32_t owner) {
  vertex_count_.fetch_add(1, std::memory_order_relaxed);
  return store_.add_vertex(p, kind, owner);
}

VertexId Triangulation::new_vertices(std::span<const Point4> points, VertexKind kind,
                                     std::uint32_t owner) {
  vertex_count_.fetch_add(points.size(), std::memory_order_relaxed);
  return store_.add_vertices(points, kind, owner);
}

void Triangulation::discard_vertex(VertexId v) {
  store_.vertex(v).kind = VertexKind::removed;
  vertex_count_.fetch_sub(1, std::memory_order_relaxed);
}

int Triangulation::orient_with(CellId c, int i, const Point4& p) const {
  const Pentatope& cell = store_.cell(c);
  const Point4* q[5];
  for (int k = 0; k < 5; ++k) q[k] = (k == i) ? &p : &store_.point(cell.v[k]);
  return orient4(*q[0], *q[1], *q[2], *q[3], *q[4]);
}

bool Triangulation::in_conflict(CellId c, const Point4& p, VertexId pid) const {
  const Pentatope& cell = store_.cell(c);
  const int inf = store_.index_of(c, kInfiniteVertex);
  if (inf < 0) {
    const Point4* s[5];
    for (int k = 0; k < 5; ++k) s[k] = &store_.point(cell.v[k]);
    // Stage 1 inline decides nearly every call on generic input; the rest take the full chain.
    const int fast = detail::insphere_semi_static(s, p);
    if (fast != detail::kUndecided) return fast > 0;
    return detail::insphere4_sos_past_semi_static(s, cell.v, p, pid) > 0;
  }
  // An infinite pentatope's "circumsphere" is the open half-space beyond its hull facet; on the
  // facet's hyperplane it is the facet's circumsphere, which is where the finite neighbor's
  // circumsphere meets that hyperplane (and carries the same tie-break).
  const int o = orient_with(c, inf, p);
  if (o != 0) return o > 0;
  return in_conflict(cell.n[inf], p, pid);
}

void Triangulation::conflicts(const CellId* cells, int count, const Point4& p, VertexId pid,
                              bool* conflict) const {
  // Finite pentatopes go through the in-sphere filter four at a time (a short group is padded
  // with its first); what it leaves undecided, and infinite pentatopes, one at a time.
  const Point4* vertices[4][5];
  int index[4];
  int lanes = 0;
  std::int8_t decided[5] = {};
  if (filter_) filter_->decide(cells, count, p, decided);
  const auto flush = [&] {
    if (lanes == 1) {  // alone: the scalar filter is faster
      conflict[index[0]] = in_conflict(cells[index[0]], p, pid);
      lanes = 0;
      return;
    }
    for (int l = lanes; l < 4; ++l) std::copy(vertices[0], vertices[0] + 5, vertices[l]);
    int verdict[4];
    detail::insphere_semi_static4(vertices, p, verdict);
    for (int l = 0; l < lanes; ++l)
      conflict[index[l]] = verdict[l] != detail::kUndecided
                               ? verdict[l] > 0
                               : detail::insphere4_sos_past_semi_static(
                                     vertices[l], store_.cell(cells[index[l]]).v, p, pid) > 0;
    lanes = 0;
  };
  for (int k = 0; k < count; ++k) {
    if (decided[k] != 0) {
      conflict[k] = decided[k] > 0;
      continue;
    }
    const Pentatope& cell = store_.cell(cells[k]);
    if (store_.index_of(cells[k], kInfiniteVertex) >= 0) {
      conflict[k] = in_conflict(cells[k], p, pid);
      continue;
    }
    for (int v = 0; v < 5; ++v) vertices[lanes][v] = &store_.point(cell.v[v]);
    index[lanes++] = k;
    if (lanes == 4) flush();
  }
  if (lanes > 0) flush();
}

CellId Triangulation::locate(const Point4& p, CellId hint) const {
  CellId c = (hint != kNoCell && store_.is_live(hint)) ? hint : any_cell();
  return locate(p, c, own_, nullptr);
}

CellId Triangulation::locate(const Point4& p, CellId c, Workspace& ws, CellGuard* guard) const {
  if (store_.is_infinite(c)) {
    c = store_.cell(c).n[store_.index_of(c, kInfiniteVertex)];
    if (guard && !guard->acquire(c)) return kNoCell;
  }
  CellId previous = kNoCell;
  // Stochastic visibility walk: cross any facet that separates p from the pentatope, trying the
  // facets from a random start so that the walk cannot cycle.
  std::uint64_t& rng = ws.walk_rng;
  while (true) {
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    const int first = static_cast<int>(rng % 5);
    const Pentatope& cell = store_.cell(c);
    CellId next = kNoCell;
    for (int k = 0; k < 5; ++k) {
      const int i = (first + k) % 5;
      if (cell.n[i] == previous) continue;  // p is on the other side of the facet we came from
      if (orient_with(c, i, p) < 0) {
        next = cell.n[i];
        break;
      }
    }
    if (next == kNoCell) return c;
    if (guard && !guard->acquire(next)) return kNoCell;
    previous = c;
    c = next;
    if (store_.is_infinite(c)) return c;  // p is strictly beyond this hull facet
  }
}

void Triangulation::find_cavity(const Point4& p, VertexId pid, CellId start, Cavity& cavity) {
  find_cavity(p, pid, start, cavity, nullptr);
}

bool Triangulation::find_cavity(const Point4& p, VertexId pid, CellId start, Cavity& cavity,
                                CellGuard* guard) {
  const std::uint32_t in_cavity = next_stamp();
  const std::uint32_t rejected = in_cavity + 1;
  cavity.cells.clear();
  cavity.boundary.clear();
  store_.cell(start).mark = in_cavity;
  cavity.cells.push_back(start);
  // Breadth-first over the cavity; each neighbor is tested at most once per search thanks to the
  // stamps (a rejecting neighbor shared by several cavity pentatopes is not tested again). The
  // neighbors of a cavity pentatope not judged yet are tested together (conflicts()), then
  // handled in facet order, as one at a time: the same cavity, in the same order.
  for (std::size_t k = 0; k < cavity.cells.size(); ++k) {
    const CellId c = cavity.cells[k];
    CellId untested[5];
    int count = 0;
    for (const CellId d : store_.cell(c).n) {
      const std::uint32_t mark = store_.cell(d).mark;
      if (mark == in_cavity || mark == rejected) continue;
      if (guard && !guard->acquire(d)) return false;
      untested[count++] = d;
    }
    bool conflict[5];
    conflicts(untested, count, p, pid, conflict);
    for (int i = 0, t = 0; i < 5; ++i) {
      const CellId d = store_.cell(c).n[i];
      Pentatope& neighbor = store_.cell(d);
      if (neighbor.mark == in_cavity) continue;
      if (neighbor.mark != rejected) {
        if (conflict[t++]) {
          neighbor.mark = in_cavity;
          cavity.cells.push_back(d);
          // Its neighbors are tested soon: start their loads now (memory latency dominates).
          for (CellId far : neighbor.n) __builtin_prefetch(&store_.cell(far));
          if (filter_) filter_->prefetch(neighbor.n, 5);
          continue;
        }
        neighbor.mark = rejected;
      }
      cavity.boundary.push_back({c, i});
    }
  }
  return true;
}

CellId Triangulation::commit(const Cavity& cavity, VertexId pid, Workspace& ws) {
  // Pass 1: one new pentatope per boundary facet (the facet joined to the new vertex, in the
  // slot of the vertex it replaces, which keeps the orientation positive). The cavity
  // pentatope's neighbor slot is overwritten with the new pentatope: pass 2 reads it there.
  std::vector<CellId>& created = ws.created;
  CellAllocator& cells = *ws.cells;
  created.clear();
  for (const Cavity::Facet& f : cavity.boundary) {
    Pentatope& old_cell = store_.cell(f.cell);
    VertexId v[5] = {old_cell.v[0], old_cell.v[1], old_cell.v[2], old_cell.v[3], old_cell.v[4]};
    v[f.index] = pid;
    const CellId outside = old_cell.n[f.index];
    const CellId n = store_.create_cell(v, cells);
    store_.cell(n).n[f.index] = outside;
    Pentatope& out = store_.cell(outside);
    out.n[store_.neighbor_index(outside, f.cell)] = n;
    store_.cell(f.cell).n[f.index] = n;
    created.push_back(n);
  }

  // Pass 2: link the new pentatopes to each other. Each facet of a new pentatope that contains
  // the new vertex is that vertex plus a triangle ("ridge") of the cavity boundary, and each
  // such ridge lies in exactly two new pentatopes: a small hash table keyed by the ridge's sorted
  // vertex ids pairs them (BUILD-NOTES: a ridge walk through the old cavity cost more, in cache
  // misses on the cavity's stamps).
  // New pentatopes made from two facets of the same cavity pentatope c share the facet that
  // c's two replaced vertices leave: pair those at once (boundary facets of one pentatope are
  // consecutive in the cavity), and hash only the rest.
  for (std::size_t k = 0; k < created.size();) {
    std::size_t end = k + 1;
    while (end < created.size() && cavity.boundary[end].cell == cavity.boundary[k].cell) ++end;
    for (std::size_t a = k; a < end; ++a)
      for (std::size_t b = a + 1; b < end; ++b) {
        store_.cell(created[a]).n[cavity.boundary[b].index] = created[b];
        store_.cell(created[b]).n[cavity.boundary[a].index] = created[a];
      }
    k = end;
  }
  RidgeTable& ridges = ws.ridges;
  ridges.begin(2 * created.size());  // each ridge is offered twice: at most 2 per new cell
  for (std::size_t k = 0; k < created.size(); ++k) {
    const CellId n = created[k];
    const int slot_p = cavity.boundary[k].index;
    Pentatope& cell = store_.cell(n);
    for (int j = 0; j < 5; ++j) {
      if (j == slot_p || cell.n[j] != kNoCell) continue;
      const auto& slots = kRidgeSlots[slot_p][j];
      VertexId r[3] = {cell.v[slots[0]], cell.v[slots[1]], cell.v[slots[2]]};
      const RidgeTable::Match match = ridges.pair(r, n, j);
      if (match.cell != kNoCell) {
        cell.n[j] = match.cell;
        store_.cell(match.cell).n[match.slot] = n;
      }
    }
  }

  for (CellId n : created)
    for (VertexId u : store_.cell(n).v) store_.vertex(u).cell = n;
  for (CellId c : cavity.cells) store_.destroy_cell(c, cells);
  any_cell_.store(created.front(), std::memory_order_relaxed);
  return created.front();
}

Triangulation::InsertResult Triangulation::insert(const Point4& p, VertexKind kind, CellId hint) {
  for (double x : p)
    if (!std::isfinite(x)) throw std::invalid_argument("Triangulation::insert: non-finite point");
  if (dimension_ < 4) return insert_pending(p, kind);

  const CellId located = locate(p, hint);
  if (!store_.is_infinite(located)) {
    for (VertexId u : store_.cell(located).v)
      if (store_.point(u) == p) return {u, false, located};
  }
  const VertexId v = new_vertex(p, kind, 0);
  Cavity& cavity = own_.cavity;
  find_cavity(p, v, located, cavity);
  const CellId c = commit(cavity, v);
  return {v, true, c};
}

void Triangulation::insert_vertex_into_mesh(VertexId v, CellId hint, CellId* last) {
  const Point4 p = store_.point(v);
  const CellId located = locate(p, hint);
  find_cavity(p, v, located, own_.cavity);
  *last = commit(own_.cavity, v);
}

std::vector<VertexId> Triangulation::insert_all(std::span<const Point4> points, VertexKind kind) {
  std::vector<VertexId> ids(points.size(), kNoVertex);
  CellId hint = kNoCell;
  for (std::size_t i : spatial_order(points)) {
    const InsertResult r = insert(points[i], kind, hint);
    ids[i] = r.vertex;
    if (r.cell != kNoCell) hint = r.cell;
  }
  return ids;
}

}  // namespace mesh4d::delaunay
