// Closing the pinches that the repair (refiner_junctions.cpp) leaves, by relabeling.
//
// Around a triangle t the pentatopes form a cycle; a label's region is pinched at t when it
// occupies two or more separate arcs of that cycle (link_labels.h). Where three labels meet at
// a sharp junction (the time caps, the valve plane), inserting more surface points there does
// not converge: each new point makes new small pentatopes whose circumcenters again fall on
// alternating sides. Moving the pentatopes of the shorter arcs (or of the gaps between them) to
// a neighboring label joins the arcs. A move is allowed only when the moved pentatope has its
// five vertices on ∂Ω (so every boundary tetrahedron still does, now and after later changes
// around it), and a pentatope that enters the output meets the quality bounds; the
// triangulation itself does not change. The moved pentatopes are the exception to "the label
// of a pentatope is the label at its circumcenter"; RefineResult::relabeled counts them.
#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "delaunay/geometry.h"
#include "refine/link_labels.h"
#include "refine/refiner.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;
using domain::Label;

constexpr int kRelabelRounds = 32;
constexpr int kMoveDepth = 3;  // sets of moves at one pinch: up to three joins
constexpr long kNotAllowed = std::numeric_limits<long>::min();

using Triangle = std::array<mesh4d::VertexId, 3>;

// The ten triangles of a pentatope, each with its vertices sorted.
std::array<Triangle, 10> triangles_of(const mesh4d::VertexId (&vertices)[5]) {
  std::array<mesh4d::VertexId, 5> v;
  std::copy_n(vertices, 5, v.begin());
  std::sort(v.begin(), v.end());
  std::array<Triangle, 10> out;
  int k = 0;
  for (int a = 0; a < 5; ++a)
    for (int b = a + 1; b < 5; ++b)
      for (int d = b + 1; d < 5; ++d) out[k++] = {v[a], v[b], v[d]};
  return out;
}

}  // namespace

std::vector<Refiner::PinchedTriangle> Refiner::pinches_on(const std::vector<CellId>& cells) const {
  std::vector<std::pair<Triangle, CellId>> triangles;
  for (CellId c : cells)
    for (const Triangle& t : triangles_of(tri_.store().cell(c).v)) triangles.push_back({t, c});
  std::sort(triangles.begin(), triangles.end());
  std::vector<PinchedTriangle> pinched;
  for (std::size_t i = 0; i < triangles.size(); ++i)
    if (i == 0 || triangles[i].first != triangles[i - 1].first)
      pinches_at(triangles[i].second, triangles[i].first, &pinched);
  return pinched;
}

std::vector<std::vector<Refiner::Move>> Refiner::relabel_options(const PinchedTriangle& p) const {
  std::vector<CellId> cycle;
  std::vector<int> crossed;
  link_cycle(p.facets.front().first, p.triangle, cycle, crossed);
  std::vector<Label> labels(cycle.size());
  for (std::size_t i = 0; i < cycle.size(); ++i) labels[i] = output_label(cycle[i]);
  std::vector<std::vector<Move>> out;
  std::vector<Label> seen;
  for (Label l : labels) {
    if (l == 0 || std::find(seen.begin(), seen.end(), l) != seen.end()) continue;
    seen.push_back(l);
    if (label_arcs(labels, l, true).size() < 2) continue;
    for (const LinkMoves& o : joining_moves(labels, l)) {
      if (o.empty()) continue;
      std::vector<Label> after = labels;
      for (const auto& [i, to] : o) after[i] = to;
      if (split_labels(after) != 0) continue;  // must join every label around t
      std::vector<Move> moves;
      for (const auto& [i, to] : o) moves.push_back({cycle[i], to});
      out.push_back(std::move(moves));
    }
  }
  return out;
}

bool Refiner::movable(CellId c, Label from) const {
  // All five vertices on ∂Ω, not only those of the facets that separate labels once c moves: a
  // facet of c between equal labels now may separate them later, when the unpinch loop's
  // drain replaces the neighbor across it by one of the other label, and R5 cannot see that
  // facet (it looks for ∂Ω between the circumcenters, and c's center still has the neighbor's
  // label); with a free vertex, that facet would stay on the boundary. (A parallel run on the
  // merging blobs once ended with a free boundary vertex; this is one way it can happen. Every
  // bench row relabels exactly the same pentatopes with this test as with the facets' one.) A
  // pentatope that enters the output (from the background) also meets the quality bounds that
  // R3 and R4 hold inside.
  const auto& st = tri_.store();
  if (!info_[c].finite) return false;
  for (mesh4d::VertexId v : st.cell(c).v)
    if (st.vertex(v).kind != delaunay::VertexKind::feature) return false;
  if (from != 0 || label_of(c) == 0) return true;
  return !info_[c].long_radius &&
         delaunay::normalized_volume(simplex_of(c)) >= params_.sliver_bound;
}

std::vector<Label> Refiner::apply(const std::vector<Move>& moves) {
  std::vector<Label> before;
  for (const Move& m : moves) before.push_back(label_of(m.cell)), set_label(m.cell, m.to);
  return before;
}

void Refiner::undo(const std::vector<Move>& moves, const std::vector<Label>& before) {
  for (std::size_t i = moves.size(); i-- > 0;) set_label(moves[i].cell, before[i]);
}

long Refiner::relabel_gain(const std::vector<Move>& moves) {
  // The change in the number of pinches on every triangle of the moved pentatopes (the only
  // triangles whose cycles a move changes), or kNotAllowed.
  std::vector<CellId> cells;
  for (const Move& m : moves) cells.push_back(m.cell);
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<Label> from(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) from[i] = label_of(cells[i]);
  const long before = static_cast<long>(pinches_on(cells).size());
  const std::vector<Label> saved = apply(moves);
  bool allowed = true;
  for (std::size_t i = 0; i < cells.size() && allowed; ++i)
    allowed = label_of(cells[i]) == from[i] || movable(cells[i], from[i]);
  const long gain = allowed ? before - static_cast<long>(pinches_on(cells).size()) : kNotAllowed;
  undo(moves, saved);
  return gain;
}

void Refiner::extend_moves(const std::vector<Move>& base, int depth, MoveSearch& search) {
  // The pinches that `base` leaves or makes on the triangles of its pentatopes, and each way
  // to join the labels around them, added to base.
  std::vector<CellId> cells;
  for (const Move& m : base) cells.push_back(m.cell);
  const std::vector<Label> saved = apply(base);
  std::vector<std::vector<Move>> next;
  for (const PinchedTriangle& q : pinches_on(cells))
    for (auto& o : relabel_options(q)) next.push_back(std::move(o));
  undo(base, saved);
  for (const auto& o : next) {
    if (search.budget == 0) return;
    --search.budget;
    std::vector<Move> both = base;
    both.insert(both.end(), o.begin(), o.end());
    const long gain = relabel_gain(both);
    if (gain > search.best_gain ||
        (gain > 0 && gain == search.best_gain && both.size() < search.best.size())) {
      search.best = both;
      search.best_gain = gain;
    } else if (gain != kNotAllowed && gain <= 0 && depth > 1) {
      extend_moves(both, depth - 1, search);
    }
  }
}

std::size_t Refiner::relabel_pinches() {
  std::size_t moved = 0;
  shifted_.assign(tri_.store().cell_slots(), false);
  // Each accepted set of moves lowers the number of pinches. A move that joins the labels
  // around the pinched triangle but splits them around another triangle of the moved
  // pentatopes (a label checkerboard around an edge) is extended, up to kMoveDepth levels,
  // with the ways to join the labels there; one that only shifts a pinch is taken alone as a
  // last resort, moving only pentatopes that never shifted (so the shifting ends).
  for (int round = 0; round < kRelabelRounds; ++round) {
    const std::vector<PinchedTriangle> pinched = current_pinches();
    if (pinched.empty()) break;
    std::size_t moved_now = 0;
    std::vector<CellId> moved_cells;
    for (const PinchedTriangle& p : pinched) {
      MoveSearch search;
      std::vector<std::vector<Move>> shifted, starts;
      for (const auto& o : relabel_options(p)) {
        const long gain = relabel_gain(o);
        if (gain > search.best_gain ||
            (gain > 0 && gain == search.best_gain && o.size() < search.best.size()))
          search.best = o, search.best_gain = gain;
        if (gain == 0) shifted.push_back(o);
        if (gain <= 0 && gain != kNotAllowed) starts.push_back(o);
      }
      for (std::size_t i = 0; i < starts.size() && search.best.empty(); ++i)
        extend_moves(starts[i], kMoveDepth - 1, search);
      if (search.best.empty()) {
        for (const auto& o : shifted)
          if (std::none_of(o.begin(), o.end(), [&](const Move& m) { return shifted_[m.cell]; })) {
            search.best = o;
            break;
          }
        for (const Move& m : search.best) shifted_[m.cell] = true;
      }
      apply(search.best);
      moved_now += search.best.size();
      for (const Move& m : search.best) moved_cells.push_back(m.cell);
    }
    moved += moved_now;
    if (moved_now == 0) break;
    // Moves change the cycles of their pentatopes' triangles only: the pinches elsewhere stay,
    // and those triangles are looked at again (a full count per round cost up to a twelfth of a
    // patient's refinement).
    std::sort(moved_cells.begin(), moved_cells.end());
    moved_cells.erase(std::unique(moved_cells.begin(), moved_cells.end()), moved_cells.end());
    std::vector<Triangle> changed;
    for (CellId c : moved_cells)
      for (const Triangle& t : triangles_of(tri_.store().cell(c).v)) changed.push_back(t);
    std::sort(changed.begin(), changed.end());
    std::vector<PinchedTriangle> updated = pinches_on(moved_cells);
    for (const PinchedTriangle& p : pinched)
      if (!std::binary_search(changed.begin(), changed.end(), p.triangle)) updated.push_back(p);
    set_current_pinches(std::move(updated));
  }
  return moved;
}

const std::vector<Refiner::PinchedTriangle>& Refiner::current_pinches() {
  if (!pinches_current_) {
    std::vector<PinchedTriangle> counted;
    count_pinches(&counted);
    set_current_pinches(std::move(counted));
  }
  return current_pinches_;
}

void Refiner::sort_canonically(std::vector<PinchedTriangle>& pinches) const {
  // Every facet of a pinch lies in a pentatope of the pinched region: its label is the pinch's.
  for (PinchedTriangle& p : pinches) std::sort(p.facets.begin(), p.facets.end());
  std::sort(
      pinches.begin(), pinches.end(), [&](const PinchedTriangle& a, const PinchedTriangle& b) {
        const Label la = label_of(a.facets.front().first), lb = label_of(b.facets.front().first);
        return a.triangle != b.triangle ? a.triangle < b.triangle : la < lb;
      });
}

void Refiner::set_current_pinches(std::vector<PinchedTriangle> pinches) {
  sort_canonically(pinches);
  current_pinches_ = std::move(pinches);
  pinches_current_ = true;
}

std::size_t Refiner::remove_free_vertices_at_pinches() {
  // The free vertices of the pentatopes around each pinched triangle: they stop the
  // relabeling there (a moved pentatope would put them on the boundary).
  const auto& st = tri_.store();
  const std::vector<PinchedTriangle> pinched = current_pinches();
  std::vector<mesh4d::VertexId> free;
  std::vector<CellId> cycle;
  std::vector<int> crossed;
  for (const PinchedTriangle& p : pinched) {
    link_cycle(p.facets.front().first, p.triangle, cycle, crossed);
    for (CellId c : cycle)
      for (mesh4d::VertexId v : st.cell(c).v)
        if (v != delaunay::kInfiniteVertex && st.vertex(v).kind == delaunay::VertexKind::free)
          free.push_back(v);
  }
  std::sort(free.begin(), free.end());
  free.erase(std::unique(free.begin(), free.end()), free.end());
  std::size_t removed = 0;
  std::vector<CellId> created;
  for (mesh4d::VertexId v : free) {
    created.clear();
    if (!tri_.remove(v, &created)) continue;
    ++removed;
    pinches_current_ = false;
    std::vector<CellId> live;
    for (CellId c : created)
      if (st.is_live(c)) live.push_back(c);
    admit(live);
  }
  return removed;
}

}  // namespace mesh4d::refine
