// Vertex removal (the refiner's R5): the hole left by a vertex's star is filled with the
// pentatopes of the Delaunay triangulation of its link that conflict with the removed vertex.
//
// Why that is right: the star of v in DT(P) is also the star of v in DT(link ∪ {v}); inserting v
// into DT(link) replaces exactly its conflict region by that star, so the conflict region fills
// the hole, and its pentatopes are Delaunay in P \ {v}. The fill is gift-wrapped and proven
// Delaunay (hole_filling.h); when the proof fails, it is read from the link's own triangulation,
// built with the same perturbation (vertices inserted oldest first keep the global age order).
// Either way the glued result is the unique perturbed Delaunay triangulation of the remaining
// vertices.
#include <algorithm>
#include <array>
#include <stdexcept>

#include "delaunay/hole_filling.h"
#include "delaunay/predicates.h"
#include "delaunay/triangulation.h"

namespace mesh4d::delaunay {
namespace {

// Adds id to an open-addressing set of 32-bit ids (a power-of-two size, `empty` in the free
// slots); false when it was there already. The star and the link each keep one.
bool insert_once(std::vector<std::uint32_t>& set, std::uint32_t id, std::uint32_t empty) {
  const std::size_t mask = set.size() - 1;
  for (std::size_t i = (id * 0x9E3779B1u) & mask;; i = (i + 1) & mask) {
    if (set[i] == id) return false;
    if (set[i] == empty) {
      set[i] = id;
      return true;
    }
  }
}

}  // namespace

bool Triangulation::collect_star(VertexId v, std::vector<CellId>& star, CellGuard* guard) const {
  star.clear();
  star.push_back(store_.vertex(v).cell);
  if (guard && !guard->acquire(star[0])) return false;
  // Neighbors across facets that contain v are incident to v too. A star has some 30 to 150
  // pentatopes: the ones seen go in a small open-addressing set (a linear search of the star
  // for each neighbor was 5 % of the refinement). Local, so that const readers may run at once.
  std::size_t size = 256;
  thread_local std::vector<CellId> seen;  // reused: a heap block per call cost more than filling
  seen.assign(size, kNoCell);
  const auto insert = [&](CellId c) { return insert_once(seen, c, kNoCell); };
  insert(star[0]);
  for (std::size_t k = 0; k < star.size(); ++k) {
    if (2 * star.size() > size) {  // keep the table at most half full
      size *= 4;
      seen.assign(size, kNoCell);
      for (CellId c : star) insert(c);
    }
    const Pentatope& cell = store_.cell(star[k]);
    for (int i = 0; i < 5; ++i) {
      if (cell.v[i] == v) continue;
      const CellId d = cell.n[i];
      if (insert(d)) {
        if (guard && !guard->acquire(d)) return false;
        star.push_back(d);
      }
    }
  }
  return true;
}

void Triangulation::fill_from_link_triangulation(VertexId v, const std::vector<VertexId>& link,
                                                 std::vector<FillCell>& fill) const {
  // The local Delaunay triangulation of the link, oldest vertex first: local id k+1 is link[k].
  // One per thread, reused: building a fresh one (its blocks, its tables) for every removal
  // cost more than the few dozen insertions into it.
  thread_local Triangulation local(8);
  local.reset();
  CellId hint = kNoCell;
  for (VertexId u : link) {
    const InsertResult r = local.insert(store_.point(u), VertexKind::free, hint);
    if (r.cell != kNoCell) hint = r.cell;
  }
  // Its pentatopes in conflict with v (under the global ids) fill the hole. v lies strictly
  // inside the hull of its link, so no infinite local pentatope can conflict with it.
  const Point4 p = store_.point(v);
  const PentatopeStore& ls = local.store();
  fill.clear();
  for (CellId c = 0; c < ls.cell_slots(); ++c) {
    if (!ls.is_live(c) || ls.is_infinite(c)) continue;
    FillCell f;
    const Point4* s[5];
    for (int i = 0; i < 5; ++i) {
      f.v[i] = link[ls.cell(c).v[i] - 1];
      s[i] = &store_.point(f.v[i]);
    }
    if (insphere4_sos(s, f.v, p, v) > 0) fill.push_back(f);
  }
}

bool Triangulation::remove(VertexId v, std::vector<CellId>* created) {
  return remove(v, created, own_, nullptr) == RemoveResult::removed;
}

Triangulation::RemoveResult Triangulation::remove(VertexId v, std::vector<CellId>* created,
                                                  Workspace& ws, CellGuard* guard) {
  if (dimension_ < 4 || v == kInfiniteVertex || v >= store_.vertex_slots())
    return RemoveResult::refused;
  const Vertex& vertex = store_.vertex(v);
  if (vertex.kind == VertexKind::removed || vertex.cell == kNoCell) return RemoveResult::refused;

  // With a guard, the star's pentatopes are claimed (so all of v's link is held); the
  // pentatopes beyond the link's facets share four held vertices and need no claim.
  thread_local std::vector<CellId> star;
  if (!collect_star(v, star, guard)) return RemoveResult::conflict;
  // The link's vertices, each once (in the order first seen: the wrap does not depend on it; a
  // sort of the star's 600 vertex ids was a twentieth of a removal).
  thread_local std::vector<VertexId> link;
  link.clear();
  {
    std::size_t size = 64;
    while (size < 8 * star.size()) size *= 2;
    thread_local std::vector<VertexId> seen;
    seen.assign(size, kNoVertex);
    for (CellId c : star) {
      if (store_.is_infinite(c)) return RemoveResult::refused;  // a hull vertex: not closable
      for (VertexId u : store_.cell(c).v)
        if (u != v && insert_once(seen, u, kNoVertex)) link.push_back(u);
    }
  }

  // The hole's boundary: the facets of the star opposite v, with the pentatope beyond each.
  thread_local std::vector<HoleFacet> hole;
  thread_local std::vector<FillCell> fill;
  hole.clear();
  for (CellId c : star) {
    const int iv = store_.index_of(c, v);
    const CellId outside = store_.cell(c).n[iv];
    hole.push_back({c, iv, outside, store_.neighbor_index(outside, c)});
  }
  ++hole_counters().holes;
  if (!hole_counters().wrap || !wrap_hole(store_, hole, link, fill)) {
    ++hole_counters().fallbacks;
    std::sort(link.begin(), link.end());  // oldest first, as the perturbation orders them
    fill_from_link_triangulation(v, link, fill);
    if (!link_fill(store_, hole, fill))
      throw std::logic_error("Triangulation::remove: link triangulation does not fit the hole");
  }

  // Create the new pentatopes, then link them to each other and to the hole's boundary.
  thread_local std::vector<CellId> made;
  made.clear();
  for (const FillCell& f : fill) made.push_back(store_.create_cell(f.v, *ws.cells));
  for (std::size_t x = 0; x < fill.size(); ++x) {
    Pentatope& cell = store_.cell(made[x]);
    for (int i = 0; i < 5; ++i) {
      if (fill[x].n[i] >= 0) {
        cell.n[i] = made[fill[x].n[i]];
        continue;
      }
      const HoleFacet& h = hole[~fill[x].n[i]];
      cell.n[i] = h.outside;
      store_.cell(h.outside).n[h.outside_slot] = made[x];
    }
  }
  for (CellId g : made) {
    for (VertexId u : store_.cell(g).v) store_.vertex(u).cell = g;
    if (created) created->push_back(g);
  }
  for (CellId c : star) store_.destroy_cell(c, *ws.cells);
  store_.vertex(v).cell = kNoCell;
  store_.vertex(v).kind = VertexKind::removed;
  vertex_count_.fetch_sub(1, std::memory_order_relaxed);
  any_cell_.store(made.front(), std::memory_order_relaxed);
  return RemoveResult::removed;
}

}  // namespace mesh4d::delaunay
