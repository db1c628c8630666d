#include "refine/extra_pieces.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <unordered_set>

#include "domain/label_pieces.h"
#include "refine/manifold_relabeling.h"
#include "support/union_find.h"

namespace mesh4d::refine {

using delaunay::CellId;
using domain::Label;

namespace {

// How many voxels a walk may visit before it gives up (the piece then stays).
constexpr std::size_t kWalkLimit = std::size_t{1} << 16;

// The largest piece looked at, in pentatopes: the cut-off pieces seen on the patients have one
// to three; a larger piece is a region the image may well have, and moving it would change the
// geometry by more than a pentatope's size.
constexpr std::size_t kMaxPiece = 64;

// The voxel nearest to p, clamped to the image.
std::size_t voxel_of(const domain::LabelImage4& image, const Point4& p) {
  const auto u = image.to_index(p);
  std::size_t c[4];
  for (int a = 0; a < 4; ++a) {
    const double r = std::round(u[a]);
    const double hi = static_cast<double>(image.dims()[a] - 1);
    c[a] = static_cast<std::size_t>(std::clamp(r, 0.0, hi));
  }
  return image.linear_index(c[0], c[1], c[2], c[3]);
}

}  // namespace

ExtraPieces ManifoldRelabeling::remove_extra_pieces() {
  ExtraPieces out;
  const auto& st = state_.tri.store();
  const auto& image = state_.oracle.image();
  const std::vector<double>& beta = state_.oracle.label_offsets();
  // The regions' facet-connected pieces.
  support::UnionFind pieces(st.cell_slots());
  std::vector<CellId> output;
  for (CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c)) continue;
    const Label l = state_.output_label(c);
    if (l == 0) continue;
    output.push_back(c);
    for (CellId n : st.cell(c).n)
      if (n < c && st.is_live(n) && state_.output_label(n) == l) pieces.join(c, n);
  }
  std::unordered_map<std::size_t, std::vector<CellId>> members;  // root -> its pentatopes
  for (CellId c : output) members[pieces.find(c)].push_back(c);
  std::unordered_map<Label, std::size_t> count_by_label;
  for (const auto& [root, cells] : members) ++count_by_label[state_.output_label(cells[0])];
  bool several = false;
  for (const auto& [l, n] : count_by_label) several |= n > 1;
  if (!several) return out;

  // Each piece's circumcenters' voxels, and which piece holds each such voxel.
  std::unordered_map<std::size_t, std::size_t> holder;  // voxel -> root
  holder.reserve(output.size());
  for (CellId c : output) holder[voxel_of(image, state_.info[c].center)] = pieces.find(c);
  // The small pieces of labels with several, smallest first; never a label's largest piece.
  std::unordered_map<Label, std::size_t> largest;  // label -> root
  for (const auto& [root, cells] : members) {
    const Label l = state_.output_label(cells[0]);
    const auto [it, inserted] = largest.try_emplace(l, root);
    if (!inserted && members[it->second].size() < cells.size()) it->second = root;
  }
  std::vector<std::pair<std::size_t, std::size_t>> order;  // (size, root)
  for (const auto& [root, cells] : members)
    if (cells.size() <= kMaxPiece && largest[state_.output_label(cells[0])] != root)
      order.push_back({cells.size(), root});
  std::sort(order.begin(), order.end());
  std::unordered_set<std::size_t> removed;

  for (const auto& [size, root] : order) {
    const std::vector<CellId>& cells = members[root];
    const Label l = state_.output_label(cells[0]);
    // Does the image join this piece to another piece of its label still there? A walk through
    // the voxels the label function joins (label_pieces.h), from those of its circumcenters.
    std::vector<std::size_t> frontier;
    std::unordered_set<std::size_t> seen;
    for (CellId c : cells) {
      const std::size_t v = voxel_of(image, state_.info[c].center);
      if (image.at(v) == l && seen.insert(v).second) frontier.push_back(v);
    }
    bool joined = false;
    while (!frontier.empty() && !joined && seen.size() < kWalkLimit) {
      const std::size_t v = frontier.back();
      frontier.pop_back();
      if (const auto h = holder.find(v); h != holder.end() && h->second != root &&
                                         !removed.count(h->second) &&
                                         state_.output_label(members[h->second][0]) == l) {
        joined = true;
        break;
      }
      domain::for_each_joined_neighbor(image, beta, v, [&](std::size_t j) {
        if (seen.insert(j).second) frontier.push_back(j);
      });
    }
    if (!joined) continue;
    ++out.found;
    // Each pentatope to the label most of its neighbors outside the piece have.
    std::vector<Move> moves;
    const std::unordered_set<CellId> inside(cells.begin(), cells.end());
    for (CellId c : cells) {
      std::unordered_map<Label, int> votes;
      for (CellId n : st.cell(c).n)
        if (!inside.count(n)) ++votes[state_.output_label(n)];
      int best = 0;
      Label to = l;
      for (const auto& [label, n] : votes)
        if (label != l && (n > best || (n == best && label < to))) best = n, to = label;
      if (to == l) to = 0;  // enclosed by the piece's own label elsewhere only: not output
      moves.push_back({c, to});
    }
    stars_.clear();
    current_.clear();
    const long gain = gain_of(moves);
    if (gain < 0 || !acceptable(moves)) continue;
    out.links_mended += static_cast<std::size_t>(gain);
    for (const Move& m : moves) state_.set_label(m.cell, m.to);
    removed.insert(root);
    ++out.removed;
    out.moved += moves.size();
  }
  stars_.clear();
  current_.clear();
  near_facets_.clear();
  return out;
}

}  // namespace mesh4d::refine
