#include "refine/relabeling.h"

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

#include "delaunay/geometry.h"
#include "refine/link_labels.h"

namespace mesh4d::refine {

Relabeling::Relabeling(RefinementState& state, const PinchScan& scan, Operation& operation,
                       Worker& w)
    : state_(state), scan_(scan), operation_(operation), worker_(w) {}

namespace {

using delaunay::CellId;
using domain::Label;

constexpr int kRelabelRounds = 32;
constexpr int kMoveDepth = 3;  // sets of moves at one pinch: up to three joins
constexpr long kNotAllowed = std::numeric_limits<long>::min();

}  // namespace

std::vector<std::vector<Relabeling::Move>> Relabeling::relabel_options(
    const PinchedTriangle& p) const {
  std::vector<CellId> cycle;
  std::vector<int> crossed;
  scan_.link_cycle(p.facets.front().first, p.triangle, cycle, crossed);
  std::vector<Label> labels(cycle.size());
  for (std::size_t i = 0; i < cycle.size(); ++i) labels[i] = state_.output_label(cycle[i]);
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

bool may_relabel(const RefinementState& state, CellId c, Label from) {
  // All five vertices on ∂Ω, not only those of the facets that separate labels once c moves: a
  // facet of c between equal labels now may separate them later, when the unpinch loop's
  // drain replaces the neighbor across it by one of the other label, and R5 cannot see that
  // facet (it looks for ∂Ω between the circumcenters, and c's center still has the neighbor's
  // label); with a free vertex, that facet would stay on the boundary. (A parallel run on the
  // merging blobs once ended with a free boundary vertex; this is one way it can happen. Every
  // bench row relabels exactly the same pentatopes with this test as with the facets' one.) A
  // pentatope that enters the output (from the background) also meets the quality bounds that
  // R3 and R4 hold inside.
  const auto& st = state.tri.store();
  if (!state.info[c].finite) return false;
  for (mesh4d::VertexId v : st.cell(c).v)
    if (st.vertex(v).kind != delaunay::VertexKind::feature) return false;
  if (from != 0 || state.label_of(c) == 0) return true;
  return !state.info[c].long_radius &&
         delaunay::normalized_volume(state.simplex_of(c)) >= state.params.sliver_bound;
}

bool Relabeling::movable(CellId c, Label from) const {
  return may_relabel(state_, c, from);
}

std::vector<Label> Relabeling::apply(const std::vector<Move>& moves) {
  std::vector<Label> before;
  for (const Move& m : moves)
    before.push_back(state_.label_of(m.cell)), state_.set_label(m.cell, m.to);
  return before;
}

void Relabeling::undo(const std::vector<Move>& moves, const std::vector<Label>& before) {
  for (std::size_t i = moves.size(); i-- > 0;) state_.set_label(moves[i].cell, before[i]);
}

long Relabeling::relabel_gain(const std::vector<Move>& moves) {
  // The change in the number of pinches on every triangle of the moved pentatopes (the only
  // triangles whose cycles a move changes), or kNotAllowed.
  std::vector<CellId> cells;
  for (const Move& m : moves) cells.push_back(m.cell);
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  std::vector<Label> from(cells.size());
  for (std::size_t i = 0; i < cells.size(); ++i) from[i] = state_.label_of(cells[i]);
  const long before = static_cast<long>(scan_.pinches_on(cells).size());
  const std::vector<Label> saved = apply(moves);
  bool allowed = true;
  for (std::size_t i = 0; i < cells.size() && allowed; ++i)
    allowed = state_.label_of(cells[i]) == from[i] || movable(cells[i], from[i]);
  const long gain =
      allowed ? before - static_cast<long>(scan_.pinches_on(cells).size()) : kNotAllowed;
  undo(moves, saved);
  return gain;
}

void Relabeling::extend_moves(const std::vector<Move>& base, int depth, MoveSearch& search) {
  // The pinches that `base` leaves or makes on the triangles of its pentatopes, and each way
  // to join the labels around them, added to base.
  std::vector<CellId> cells;
  for (const Move& m : base) cells.push_back(m.cell);
  const std::vector<Label> saved = apply(base);
  std::vector<std::vector<Move>> next;
  for (const PinchedTriangle& q : scan_.pinches_on(cells))
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

std::size_t Relabeling::relabel_pinches() {
  std::size_t moved = 0;
  shifted_.assign(state_.tri.store().cell_slots(), false);
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
      for (const Triangle& t : triangles_of(state_.tri.store().cell(c).v)) changed.push_back(t);
    std::sort(changed.begin(), changed.end());
    std::vector<PinchedTriangle> updated = scan_.pinches_on(moved_cells);
    for (const PinchedTriangle& p : pinched)
      if (!std::binary_search(changed.begin(), changed.end(), p.triangle)) updated.push_back(p);
    set_current(std::move(updated));
  }
  return moved;
}

const std::vector<PinchedTriangle>& Relabeling::current_pinches() {
  if (!current_known_) {
    std::vector<PinchedTriangle> counted;
    scan_.count(&counted);
    set_current(std::move(counted));
  }
  return current_;
}

void Relabeling::set_current(std::vector<PinchedTriangle> pinches) {
  // In periodic time, the middle sheet's pinches only: a copy of one elsewhere would be mended
  // on its own, perhaps another way, and both ways would reach every sheet (set_label).
  std::erase_if(pinches, [&](const PinchedTriangle& p) { return !scan_.counted(p); });
  scan_.sort_canonically(pinches);
  current_ = std::move(pinches);
  current_known_ = true;
}

std::size_t Relabeling::remove_free_vertices_at_pinches() {
  // The free vertices of the pentatopes around each pinched triangle: they stop the
  // relabeling there (a moved pentatope would put them on the boundary).
  const auto& st = state_.tri.store();
  const std::vector<PinchedTriangle> pinched = current_pinches();
  std::vector<mesh4d::VertexId> free;
  std::vector<CellId> cycle;
  std::vector<int> crossed;
  for (const PinchedTriangle& p : pinched) {
    scan_.link_cycle(p.facets.front().first, p.triangle, cycle, crossed);
    for (CellId c : cycle)
      for (mesh4d::VertexId v : st.cell(c).v)
        if (v != delaunay::kInfiniteVertex && st.vertex(v).kind == delaunay::VertexKind::free)
          free.push_back(v);
  }
  if (state_.covering.active()) {  // their copies go too: the point set stays periodic
    const std::size_t n = free.size();
    for (std::size_t i = 0; i < n; ++i)
      for (int periods : {-2, -1, 1, 2})
        if (const auto t = state_.covering.twin(state_.tri, free[i], periods);
            t != delaunay::kNoVertex)
          free.push_back(t);
  }
  std::sort(free.begin(), free.end());
  free.erase(std::unique(free.begin(), free.end()), free.end());
  std::size_t removed = 0;
  std::vector<CellId> created;
  for (mesh4d::VertexId v : free) {
    created.clear();
    if (!state_.tri.remove(v, &created)) continue;
    ++removed;
    current_known_ = false;
    std::vector<CellId> live;
    for (CellId c : created)
      if (st.is_live(c)) live.push_back(c);
    operation_.admit(worker_, live);
  }
  return removed;
}

}  // namespace mesh4d::refine
