#include "refine/piece_matching.h"

#include <algorithm>
#include <iterator>
#include <unordered_map>
#include <unordered_set>

#include "refine/manifold_relabeling.h"
#include "support/concurrent_union_find.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using domain::FacePieces;
using domain::Label;

namespace {

// The largest piece that may take its neighbors' label, in pentatopes: the cut-off pieces seen
// on the patients have one to three; moving a larger one would change the geometry by more than
// a pentatope's size (it is bridged instead).
constexpr std::size_t kMaxRemoved = 64;
// The most pentatopes a bridge takes, and how many bridges are weighed per piece.
constexpr int kMaxBridge = 8;
constexpr std::size_t kBridgesWeighed = 16;
// How deep a cut goes, in layers of pentatopes; how far a walk (the search for a bridge, the
// check that a cut separates) goes before it gives up.
constexpr int kMaxCutLayers = 3;
constexpr std::size_t kWalkLimit = std::size_t{1} << 15;
// How many failing links a cut may leave to the manifold sampling (where both pieces touch one
// vertex, no relabeling separates them: the sampling's points do).
constexpr std::size_t kSpareLinks = 8;
// Passes over the pieces (each acts on pieces that no earlier action of the pass touched).
constexpr int kPasses = 3;
// Pentatope slots per thread, at least, when the pieces are found on the job's threads.
constexpr std::size_t kMinShare = std::size_t{1} << 16;

// The piece of the voxel nearest to a pentatope's circumcenter, by cell, looked up the first
// time a pass finds the pentatope in an output region (the passes move labels, not
// circumcenters: one lookup serves them all; the background's pentatopes, more than a third of a
// heart's, are never looked up).
class NearestPieces {
 public:
  explicit NearestPieces(const RefinementState& state)
      : state_(state), piece_(state.tri.store().cell_slots(), kNotLookedUp) {}
  /// Safe on the job's threads for distinct cells.
  std::uint32_t operator()(CellId c) {
    std::uint32_t& p = piece_[c];
    if (p == kNotLookedUp) p = state_.oracle.nearest_piece(state_.info[c].center);
    return p;
  }

 private:
  static constexpr std::uint32_t kNotLookedUp = FacePieces::kNoPiece - 1;
  const RefinementState& state_;
  std::vector<std::uint32_t> piece_;
};

// The regions' facet-connected pieces, and the image piece each pentatope stands for.
struct RegionPieces {
  RegionPieces(const RefinementState& state, NearestPieces& nearest)
      : found(state.tri.store().cell_slots()) {
    const auto& st = state.tri.store();
    const std::size_t slots = st.cell_slots();
    image_piece.assign(slots, FacePieces::kNoPiece);
    // Each pentatope's label and image piece on the job's threads (the labels are computed at
    // most once each, atomically: RefinementState::label_of), then the pieces joined on them
    // too: a piece's root is its first pentatope, whatever the threads, and so are the ties
    // that the roots break below.
    std::vector<Label> label(slots, 0);
    const std::vector<FacePieces::Piece>& image_pieces = state.oracle.pieces().pieces;
    const unsigned parts = support::parts_for(slots, kMinShare, working_threads(state.params));
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(slots, part, parts);
      for (std::size_t c = begin; c < end; ++c) {
        if (!st.is_live(static_cast<CellId>(c))) continue;
        // A ghost's region is left out, as the background is: it is not output.
        Label l = state.output_label(static_cast<CellId>(c));
        if (!state.output_region(l)) l = 0;
        label[c] = l;
        if (l == 0) continue;
        const std::uint32_t p = nearest(static_cast<CellId>(c));
        if (p != FacePieces::kNoPiece && image_pieces[p].label == l) image_piece[c] = p;
      }
    });
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(slots, part, parts);
      for (std::size_t c = begin; c < end; ++c) {
        const Label l = label[c];
        if (l == 0) continue;
        for (CellId n : st.cell(static_cast<CellId>(c)).n)
          if (n < c && label[n] == l) found.join(c, n);
      }
    });
    // (Neighbors in the store mostly share a piece and an image piece: the last map entry is
    // kept at hand instead of a lookup per pentatope.)
    std::size_t last_root = slots;
    std::vector<CellId>* last_members = nullptr;
    for (CellId c = 0; c < slots; ++c) {
      if (label[c] == 0) continue;
      const std::size_t root = found.find(c);
      if (root != last_root) last_root = root, last_members = &members[root];
      last_members->push_back(c);
    }
    // Each image piece's owner: the piece with the most pentatopes standing for it.
    std::unordered_map<std::uint32_t, std::pair<std::size_t, std::size_t>> best;  // -> (n, root)
    for (const auto& [root, cells] : members) {
      std::unordered_map<std::uint32_t, std::size_t> count;
      std::uint32_t last_piece = FacePieces::kNoPiece;
      std::size_t* last_count = nullptr;
      for (CellId c : cells) {
        if (image_piece[c] == FacePieces::kNoPiece) continue;
        if (image_piece[c] != last_piece)
          last_piece = image_piece[c], last_count = &count[last_piece];
        ++*last_count;
      }
      for (const auto& [p, n] : count) {
        auto [it, inserted] = best.try_emplace(p, n, root);
        if (!inserted &&
            (n > it->second.first || (n == it->second.first && root < it->second.second)))
          it->second = {n, root};
      }
      auto& d = dominant[root];
      d = FacePieces::kNoPiece;
      std::size_t most = 0;
      for (const auto& [p, n] : count)
        if (n > most || (n == most && p < d)) most = n, d = p;
    }
    for (const auto& [p, owner] : best) owned[owner.second].push_back(p);
  }

  support::ConcurrentUnionFind found;
  std::vector<std::uint32_t> image_piece;                             // by cell
  std::unordered_map<std::size_t, std::vector<CellId>> members;       // root -> its pentatopes
  std::unordered_map<std::size_t, std::uint32_t> dominant;            // root -> most stood for
  std::unordered_map<std::size_t, std::vector<std::uint32_t>> owned;  // root -> image pieces
};

}  // namespace

// Whether a walk through `label`'s pentatopes from `from` meets one for which `goal` holds.
bool ManifoldRelabeling::reaches(const std::vector<CellId>& from, Label label,
                                 const std::function<bool(CellId)>& goal) const {
  const auto& st = state_.tri.store();
  std::unordered_set<CellId> seen;
  std::vector<CellId> frontier;
  for (CellId c : from)
    if (state_.output_label(c) == label && seen.insert(c).second) frontier.push_back(c);
  while (!frontier.empty()) {
    const CellId c = frontier.back();
    frontier.pop_back();
    if (goal(c) || seen.size() > kWalkLimit) return true;
    for (CellId n : st.cell(c).n)
      if (st.is_live(n) && state_.output_label(n) == label && seen.insert(n).second)
        frontier.push_back(n);
  }
  return false;
}

bool ManifoldRelabeling::apply_mended(const std::vector<Move>& moves,
                                      const std::function<bool()>& done, PieceMatching& out,
                                      bool guarded, Label label, std::size_t spare) {
  stars_.clear();
  current_.clear();
  const long gain = gain_of(moves);
  // Pinches the moves make fail their vertices' links, which must then be mended.
  if (gain == kNotAllowed || !acceptable(moves, gain < 0)) return false;
  std::vector<Label> labels;
  for (const Move& m : moves) labels.push_back(m.to), labels.push_back(state_.output_label(m.cell));
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const std::size_t before = static_cast<std::size_t>(failing_over(moves, labels, true));
  // Every move made here with the label it left, the mending's too, for the undo.
  std::vector<Move> undo;
  std::vector<VertexId> around;
  for (const Move& m : moves) {
    undo.push_back({m.cell, state_.output_label(m.cell)});
    state_.set_label(m.cell, m.to);
    for (VertexId v : state_.tri.store().cell(m.cell).v) around.push_back(v);
  }
  std::size_t moved = moves.size();
  bool kept = done();
  if (kept && gain < 0) {
    // Links the moves broke: the manifold step mends them, or all is undone.
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    if (guarded) guard_ = [&] { return !done(); }, guarded_label_ = label;
    undo_log_ = &undo;
    const Outcome mended = run(&around);
    undo_log_ = nullptr;
    guard_ = nullptr;
    moved += mended.moved;
    kept = mended.failing.size() <= before + spare && done();
    if (kept && mended.failing.size() <= before) out.links_mended += before - mended.failing.size();
    // Every pair left failing goes to the caller, also when fewer fail than before: the moves
    // may mend some links and break others (Pat02 in periodic time: a cut left its two pieces
    // touching at a vertex that nothing looked at again).
    if (kept) out.failing.insert(out.failing.end(), mended.failing.begin(), mended.failing.end());
  } else if (kept) {
    // Moves that mend more than they break may still break a link: those left are listed too.
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    const std::vector<NonManifoldVertex> left = failing_pairs_at(state_, around);
    out.failing.insert(out.failing.end(), left.begin(), left.end());
  }
  stars_.clear();
  current_.clear();
  if (!kept) {
    for (auto m = undo.rbegin(); m != undo.rend(); ++m)
      if (state_.output_label(m->cell) != m->to) state_.set_label(m->cell, m->to);
    return false;
  }
  out.links_mended += static_cast<std::size_t>(std::max(gain, 0L));
  out.moved += moved;
  return true;
}

void ManifoldRelabeling::contact_samples(const std::vector<CellId>& island, std::uint32_t piece,
                                         const std::vector<std::uint32_t>& image_piece,
                                         std::vector<RepairPoint>& out) const {
  const auto& st = state_.tri.store();
  // Where ∂Ω crosses the Voronoi edge between a and b, from both ends.
  const auto sample = [&](CellId a, CellId b) {
    if (!state_.info[a].finite || !state_.info[b].finite) return;
    for (const auto& [from, to] : {std::pair{a, b}, std::pair{b, a}}) {
      const auto z = state_.oracle.first_crossing(state_.info[from].center, state_.info[to].center);
      if (!z) continue;
      out.push_back(RepairPoint{z->point, state_.candidate(from)});
    }
  };
  // The region's pentatopes that join the island to the rest: those next to it that stand for
  // another image piece, or for none (their circumcenters lie in the label the corner has),
  // and then those next to the latter that stand for another.
  const Label l = island.empty() ? Label{0} : state_.output_label(island[0]);
  const auto of_region = [&](CellId n) { return st.is_live(n) && state_.output_label(n) == l; };
  std::vector<CellId> joining;
  for (CellId c : island)
    for (CellId n : st.cell(c).n) {
      if (!of_region(n) || image_piece[n] == piece) continue;
      sample(c, n);
      if (image_piece[n] == FacePieces::kNoPiece) joining.push_back(n);
    }
  // Each once, by id: the samples' order (their insertion order) does not hang on a hash.
  std::sort(joining.begin(), joining.end());
  joining.erase(std::unique(joining.begin(), joining.end()), joining.end());
  for (CellId c : joining)
    for (CellId n : st.cell(c).n)
      if (of_region(n) && image_piece[n] != piece && image_piece[n] != FacePieces::kNoPiece)
        sample(c, n);
}

PieceMatching ManifoldRelabeling::match_image_pieces(bool leave_links) {
  PieceMatching out;
  const auto& st = state_.tri.store();
  // The label most of c's neighbors have other than `leaving`, the moved ones as they will be.
  const auto neighbors_label = [&](CellId c, Label leaving,
                                   const std::unordered_map<CellId, Label>& moving) {
    std::unordered_map<Label, int> votes;
    for (CellId n : st.cell(c).n) {
      const auto m = moving.find(n);
      const Label l = m != moving.end() ? m->second : state_.output_label(n);
      if (l != leaving) ++votes[l];
    }
    int best = 0;
    Label to = leaving;
    for (const auto& [label, n] : votes)
      if (n > best || (n == best && label < to)) best = n, to = label;
    return to;
  };
  // Every pentatope of `cells` to its neighbors' label (those enclosed by the piece's own label
  // only, none of which the callers move, to the background).
  const auto away = [&](const std::vector<CellId>& cells, Label l) {
    std::vector<Move> moves;
    for (CellId c : cells) {
      const Label to = neighbors_label(c, l, {});
      moves.push_back({c, to == l ? Label{0} : to});
    }
    return moves;
  };

  NearestPieces nearest(state_);
  for (int pass = 0; pass < kPasses; ++pass) {
    RegionPieces pieces(state_, nearest);
    out.unseparated.clear();  // those of the last pass: the earlier ones may have been cut since
    std::unordered_set<std::size_t> touched;  // roots acted on in this pass
    std::size_t actions = 0;
    std::unordered_map<Label, std::size_t> largest;  // label -> root
    for (const auto& [root, cells] : pieces.members) {
      const Label l = state_.output_label(cells[0]);
      const auto [it, inserted] = largest.try_emplace(l, root);
      if (!inserted && pieces.members[it->second].size() < cells.size()) it->second = root;
    }

    // In periodic time only pieces of the middle sheet are acted on: their moves go to every
    // sheet (RefinementState::set_label), and a piece elsewhere may be one the covering's
    // cut-off ends made.
    const auto in_middle_sheet = [&](const std::vector<CellId>& cells) {
      return std::any_of(cells.begin(), cells.end(),
                         [&](CellId c) { return state_.covering.representative(state_.tri, c); });
    };
    // In periodic time an image piece is cut off where it is mostly the middle sheet's, not
    // where a copy of it fills a margin: that copy is cut with it (its pentatopes take their
    // twins' labels), while a cut of the copy reaches the middle sheet only in part, through
    // the twins of its pentatopes in the trusted band (Pat02 at seed 4 in a covering of 6
    // frames: the copy one period on was cut first, and then no cut separated the middle
    // sheet's island).
    const auto mostly_in_middle_sheet = [&](const std::vector<CellId>& cells) {
      const auto n = std::count_if(cells.begin(), cells.end(), [&](CellId c) {
        return state_.covering.representative(state_.tri, c);
      });
      return 2 * static_cast<std::size_t>(n) >= cells.size();
    };
    // Split: a piece that owns no image piece (or stands for none: pentatopes moved into the
    // label only), smallest first.
    std::vector<std::pair<std::size_t, std::size_t>> extra;  // (size, root)
    for (const auto& [root, cells] : pieces.members)
      if (!pieces.owned.count(root) && largest[state_.output_label(cells[0])] != root &&
          in_middle_sheet(cells))
        extra.push_back({cells.size(), root});
    std::sort(extra.begin(), extra.end());
    for (const auto& [size, piece_root] : extra) {
      const std::size_t root = piece_root;  // captured below (not a structured binding)
      const std::vector<CellId>& cells = pieces.members[root];
      const Label l = state_.output_label(cells[0]);
      ++out.extra_found;
      const auto gone = [&] { return true; };
      if (size <= kMaxRemoved && apply_mended(away(cells, l), gone, out)) {
        ++out.removed, ++actions;
        touched.insert(root);
        continue;
      }
      // A bridge: a walk of up to kMaxBridge pentatopes of other labels from the piece to
      // another of its label, which takes the label. Those whose circumcenters stand for the
      // piece's image piece first (the label function has the label nearby).
      const std::uint32_t image_piece = pieces.dominant[root];
      std::unordered_map<CellId, CellId> parent;  // walked cell -> where it came from
      std::vector<CellId> layer;
      for (CellId c : cells) parent.emplace(c, c);
      layer = cells;
      std::vector<std::vector<CellId>> bridges;
      for (int depth = 0;
           depth <= kMaxBridge && bridges.empty() && !layer.empty() && parent.size() < kWalkLimit;
           ++depth) {
        std::vector<CellId> next;
        for (CellId c : layer)
          for (CellId n : st.cell(c).n) {
            if (!st.is_live(n) || parent.count(n)) continue;
            const Label ln = state_.output_label(n);
            if (ln == l) {
              const std::size_t r = pieces.found.find(n);
              if (r == root || touched.count(r) || depth == 0) continue;
              std::vector<CellId> bridge;
              for (CellId b = c; parent.at(b) != b; b = parent.at(b)) bridge.push_back(b);
              if (bridges.size() < kBridgesWeighed) bridges.push_back(std::move(bridge));
              continue;
            }
            if (depth == kMaxBridge || !state_.info[n].finite) continue;
            parent.emplace(n, c);
            next.push_back(n);
          }
        layer = std::move(next);
      }
      const auto along = [&](const std::vector<CellId>& b) {
        std::size_t n = 0;
        for (CellId c : b) n += state_.oracle.piece_at(state_.info[c].center, l) == image_piece;
        return n;
      };
      std::stable_sort(bridges.begin(), bridges.end(),
                       [&](const auto& a, const auto& b) { return along(a) > along(b); });
      for (const std::vector<CellId>& bridge : bridges) {
        std::vector<Move> moves;
        for (CellId c : bridge) moves.push_back({c, l});
        // Joined: the piece reaches another of its label.
        const auto joined = [&] {
          return reaches(cells, l, [&](CellId c) {
            return pieces.found.find(c) != root && pieces.members.count(pieces.found.find(c));
          });
        };
        if (!apply_mended(moves, joined, out)) continue;
        ++out.bridged, ++actions;
        touched.insert(root);
        break;
      }
    }

    // Merged: a piece that owns image pieces besides its main one; each other is cut off.
    for (const auto& [root, owned] : pieces.owned) {
      if (owned.size() < 2 || touched.count(root)) continue;
      const std::vector<CellId>& cells = pieces.members[root];
      if (!in_middle_sheet(cells)) continue;
      const Label l = state_.output_label(cells[0]);
      // The piece's main image piece: of those it owns, the one most of its pentatopes stand for.
      std::unordered_map<std::uint32_t, std::size_t> count;
      for (CellId c : cells) ++count[pieces.image_piece[c]];
      std::uint32_t main = owned[0];
      for (std::uint32_t p : owned)
        if (count[p] > count[main] || (count[p] == count[main] && p < main)) main = p;
      for (std::uint32_t p : owned) {
        if (p == main) continue;
        std::vector<CellId> island, rest;
        for (CellId c : cells) (pieces.image_piece[c] == p ? island : rest).push_back(c);
        if (!mostly_in_middle_sheet(island)) continue;
        ++out.merged_found;
        // The cuts weighed: layers on either side of where the two meet, one to three deep,
        // the rest's side first (the image piece keeps its pentatopes), then the piece's own.
        std::vector<std::vector<Move>> cuts;
        for (int side = 0; side < 2; ++side) {
          const std::vector<CellId>& near = side == 0 ? island : rest;
          const std::unordered_set<CellId> far_set = [&] {
            const auto& far = side == 0 ? rest : island;
            return std::unordered_set<CellId>(far.begin(), far.end());
          }();
          std::unordered_map<CellId, Label> moving;
          std::vector<Move> moves;
          std::vector<CellId> front = near;
          for (int layer = 0; layer < kMaxCutLayers; ++layer) {
            std::vector<CellId> next;
            for (CellId c : front)
              for (CellId n : st.cell(c).n)
                if (far_set.count(n) && !moving.count(n) && state_.output_label(n) == l)
                  moving.emplace(n, l), next.push_back(n);
            if (next.empty()) break;
            // Each takes its neighbors' label, the earlier layers' as they will be.
            for (CellId c : next) moving[c] = neighbors_label(c, l, moving);
            for (CellId c : next) moves.push_back({c, moving[c]});
            front = next;
            cuts.push_back(moves);
          }
        }
        // Cut: what is left of the image piece's pentatopes reaches no other image piece's.
        const auto cut = [&] {
          const bool any = std::any_of(island.begin(), island.end(),
                                       [&](CellId c) { return state_.output_label(c) == l; });
          return any && !reaches(island, l, [&](CellId c) {
                   return pieces.image_piece[c] != FacePieces::kNoPiece &&
                          pieces.image_piece[c] != p;
                 });
        };
        // The mending may not join the piece again (no move that gives a pentatope the label
        // may undo the cut). Where that leaves links failing, the cuts are tried again with
        // the mending free (it then rejoins the piece on most tries: 5 of 6 on Pat02 at δ 5).
        bool done = false;
        for (int guarded = 1; guarded >= 0 && !done; --guarded)
          for (std::size_t k = 0; k < cuts.size() && !done; ++k)
            done = apply_mended(cuts[k], cut, out, guarded, l,
                                guarded && leave_links ? kSpareLinks : 0);
        if (!done) {
          contact_samples(island, p, pieces.image_piece, out.unseparated);
          continue;
        }
        ++out.cut, ++actions;
        touched.insert(root);
        break;
      }
    }
    if (actions == 0) break;
  }
  stars_.clear();
  current_.clear();
  near_facets_.clear();
  return out;
}

}  // namespace mesh4d::refine
