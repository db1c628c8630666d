#include "refine/link_labels.h"

#include <algorithm>

namespace mesh4d::refine {

using domain::Label;

std::vector<Arc> label_arcs(const std::vector<Label>& labels, Label l, bool of_l) {
  const std::size_t n = labels.size();
  std::vector<Arc> out;
  // Start right after a position of the other kind, so that no run wraps around the start.
  std::size_t first = n;
  for (std::size_t i = 0; i < n; ++i)
    if ((labels[i] == l) != of_l) {
      first = (i + 1) % n;
      break;
    }
  if (first == n) return {{0, n}};  // the whole cycle is of that kind
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = (first + k) % n;
    if ((labels[i] == l) != of_l) continue;
    if (!out.empty() && out.back().begin + out.back().length == first + k)
      ++out.back().length;
    else
      out.push_back({first + k, 1});
  }
  for (Arc& a : out) a.begin %= n;
  return out;
}

int split_labels(const std::vector<Label>& labels) {
  std::vector<Label> seen;
  for (Label l : labels)
    if (l != 0 && std::find(seen.begin(), seen.end(), l) == seen.end()) seen.push_back(l);
  int split = 0;
  for (Label l : seen) split += label_arcs(labels, l, true).size() > 1;
  return split;
}

std::vector<LinkMoves> joining_moves(const std::vector<Label>& labels, Label l) {
  const std::size_t n = labels.size();
  std::vector<LinkMoves> out;
  const std::vector<Arc> arcs = label_arcs(labels, l, true), gaps = label_arcs(labels, l, false);
  if (arcs.size() < 2) return out;
  // The run each option keeps: the longest first (the fewest moves), then every other one (a
  // tie, or the longest run's pentatopes may not move: around a triangle of Pat05 at the
  // paper's spacing, seed 5, gaps of three background and three myocardium pentatopes, the
  // myocardium's with free vertices, kept one pinch open when only the first gap was kept).
  const auto kept_order = [](const std::vector<Arc>& runs) {
    std::vector<std::size_t> order(runs.size());
    for (std::size_t i = 0; i < runs.size(); ++i) order[i] = i;
    const auto longest = std::max_element(
        runs.begin(), runs.end(), [](const Arc& a, const Arc& b) { return a.length < b.length; });
    std::rotate(order.begin(), order.begin() + (longest - runs.begin()),
                order.begin() + (longest - runs.begin()) + 1);
    return order;
  };
  const auto fill = [&](std::size_t kept) {
    LinkMoves moves;
    for (std::size_t g = 0; g < gaps.size(); ++g)
      if (g != kept)
        for (std::size_t k = 0; k < gaps[g].length; ++k)
          moves.emplace_back((gaps[g].begin + k) % n, l);
    return moves;
  };
  const auto cut = [&](std::size_t kept, int side) {
    LinkMoves moves;
    for (std::size_t a = 0; a < arcs.size(); ++a) {
      if (a == kept) continue;
      const Arc& arc = arcs[a];
      const Label next =
          side == 0 ? labels[(arc.begin + n - 1) % n] : labels[(arc.begin + arc.length) % n];
      for (std::size_t k = 0; k < arc.length; ++k) moves.emplace_back((arc.begin + k) % n, next);
    }
    return moves;
  };
  // As many gaps as arcs: they alternate around the cycle.
  const std::vector<std::size_t> gap_order = kept_order(gaps), arc_order = kept_order(arcs);
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    out.push_back(fill(gap_order[i]));
    out.push_back(cut(arc_order[i], 0));
    out.push_back(cut(arc_order[i], 1));
  }
  return out;
}

}  // namespace mesh4d::refine
