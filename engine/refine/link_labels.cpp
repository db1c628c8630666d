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
  if (label_arcs(labels, l, true).size() < 2) return out;
  const auto all_but_longest = [](std::vector<Arc> runs) {
    std::iter_swap(runs.begin(),
                   std::max_element(runs.begin(), runs.end(), [](const Arc& a, const Arc& b) {
                     return a.length < b.length;
                   }));
    runs.erase(runs.begin());
    return runs;
  };
  LinkMoves fill;
  for (const Arc& gap : all_but_longest(label_arcs(labels, l, false)))
    for (std::size_t k = 0; k < gap.length; ++k) fill.emplace_back((gap.begin + k) % n, l);
  out.push_back(std::move(fill));
  for (int side = 0; side < 2; ++side) {
    LinkMoves cut;
    for (const Arc& arc : all_but_longest(label_arcs(labels, l, true))) {
      const Label next =
          side == 0 ? labels[(arc.begin + n - 1) % n] : labels[(arc.begin + arc.length) % n];
      for (std::size_t k = 0; k < arc.length; ++k) cut.emplace_back((arc.begin + k) % n, next);
    }
    out.push_back(std::move(cut));
  }
  return out;
}

}  // namespace mesh4d::refine
