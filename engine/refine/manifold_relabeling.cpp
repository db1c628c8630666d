#include "refine/manifold_relabeling.h"

#include <algorithm>
#include <array>
#include <iterator>
#include <limits>
#include <map>

#include "mesh/link_topology.h"
#include "refine/link_ball.h"
#include "refine/relabeling.h"
#include "support/parallel_parts.h"
#include "support/union_find.h"

namespace mesh4d::refine {

using delaunay::CellId;
using domain::Label;
using mesh4d::VertexId;

namespace {

// Passes over the failing pairs; on the patients the count stops falling after three or four.
constexpr int kRounds = 8;
// single pentatopes, adjacent pairs, pieces around the vertex, balls in the vertex's link
constexpr int kTiers = 4;
// Seeds per side for the balls: the largest pieces of the label and of the rest around v.
constexpr std::size_t kBallSeeds = 2;
// Larger changes of a star almost never lower the count (they break the neighbors' links).
constexpr std::size_t kMaxBallMoves = 32;
// How far from ∂Ω (in Δ) the centroid of a facet that a move puts on the boundary may lie: the
// bound the tests hold every boundary to.
constexpr double kMaxSag = 0.5;
// Detours: how many failing links the first move may add, how many such moves are tried per
// failing pair, and how deep the mending of what they broke goes.
constexpr long kDetourLoss = 2;
constexpr std::size_t kDetours = 6;
constexpr int kDetourDepth = 1;
// Vertices per thread, at least, when a round's links are looked at again on the job's threads.
constexpr std::size_t kCheckShare = 64;

}  // namespace

const std::vector<CellId>& ManifoldRelabeling::star_of(VertexId u) {
  auto [it, inserted] = stars_.try_emplace(u);
  if (inserted) state_.tri.incident_cells(u, it->second);
  return it->second;
}

long ManifoldRelabeling::failing_over(const std::vector<Move>& moves,
                                      const std::vector<Label>& labels, bool current) {
  // (In periodic time the links the output has: a vertex past the middle sheet counts as its
  // twin there.)
  std::vector<VertexId> vertices;
  for (const Move& m : moves)
    for (VertexId v : state_.tri.store().cell(m.cell).v)
      if (const VertexId u = counted_vertex(state_, v); u != delaunay::kNoVertex)
        vertices.push_back(u);
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
  long failing = 0;
  for (VertexId v : vertices)
    for (Label l : labels) {
      if (!current) {
        failing += region_link_fails(state_, v, star_of(v), l);
        continue;
      }
      // The labels as they are: the same answer for every option until one is applied.
      const auto [it, inserted] = current_.try_emplace(std::uint64_t{v} << 16 | l, false);
      if (inserted) it->second = region_link_fails(state_, v, star_of(v), l);
      failing += it->second;
    }
  return failing;
}

bool ManifoldRelabeling::facet_near_surface(const std::array<VertexId, 4>& facet,
                                            double bound) const {
  const auto& st = state_.tri.store();
  Point4 centroid{};
  for (VertexId v : facet)
    for (int k = 0; k < 4; ++k) centroid[k] += 0.25 * st.point(v)[k];
  // Its vertices lie on ∂Ω: the nearest bounds the distance, and the oracle is asked only when
  // that is not enough.
  double d = std::numeric_limits<double>::infinity();
  for (VertexId v : facet) d = std::min(d, distance(st.point(v), centroid));
  if (d <= bound) return true;
  // The oracle's lower bound refuses at once; a point of ∂Ω that the ray mode (a tenth of the
  // descent's cost) finds within the bound accepts, as the descent would (it starts from the
  // ray's candidates and only comes nearer). Only what is left takes the descent.
  const auto& oracle = state_.oracle;
  if (oracle.facts(centroid).lower > bound) return false;
  const domain::SurfacePoint r =
      oracle.closest_surface_point(centroid, domain::SurfaceOracle::CfpMode::ray);
  if (r.inner != r.outer && distance(r.point, centroid) <= bound) return true;
  const domain::SurfacePoint z = oracle.closest_surface_point(centroid);
  return z.inner != z.outer && distance(z.point, centroid) <= bound;
}

bool ManifoldRelabeling::new_boundary_near_surface(const std::vector<Move>& moves,
                                                   const std::vector<Label>& old) {
  const auto& st = state_.tri.store();
  const double bound = kMaxSag * state_.params.delta;
  const auto old_label = [&](CellId c) {
    for (std::size_t i = 0; i < moves.size(); ++i)
      if (moves[i].cell == c) return old[i];
    return state_.output_label(c);
  };
  for (const Move& m : moves) {
    const auto& cell = st.cell(m.cell);
    for (int f = 0; f < 5; ++f) {
      const CellId n = cell.n[f];
      const bool boundary_now = state_.output_label(n) != m.to;
      const bool boundary_before = old_label(n) != old_label(m.cell);
      if (!boundary_now || boundary_before) continue;
      // The triangulation does not change during the step: each facet is asked once.
      std::array<VertexId, 4> key;
      for (int q = 0, k = 0; q < 5; ++q)
        if (q != f) key[k++] = cell.v[q];
      std::sort(key.begin(), key.end());
      const auto [known, inserted] = near_facets_.try_emplace(key, true);
      if (inserted) known->second = facet_near_surface(key, bound);
      if (!known->second) return false;
    }
  }
  return true;
}

long ManifoldRelabeling::gain_of(const std::vector<Move>& moves) {
  // Only the links of the moved pentatopes' vertices change, and only for the labels they
  // leave or take.
  std::vector<Label> labels, old;
  for (const Move& m : moves) labels.push_back(m.to), labels.push_back(state_.output_label(m.cell));
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const long before = failing_over(moves, labels, true);
  for (const Move& m : moves)
    old.push_back(state_.output_label(m.cell)), state_.set_label(m.cell, m.to);
  bool allowed = true;
  for (std::size_t i = 0; i < moves.size() && allowed; ++i)
    allowed = may_relabel(state_, moves[i].cell, old[i]);
  if (allowed && guard_)
    for (const Move& m : moves)
      if (m.to == guarded_label_) {
        allowed = !guard_();
        break;
      }
  const long gain = allowed ? before - failing_over(moves, labels, false) : kNotAllowed;
  for (std::size_t i = moves.size(); i-- > 0;) state_.set_label(moves[i].cell, old[i]);
  return gain;
}

bool ManifoldRelabeling::acceptable(const std::vector<Move>& moves, bool pinches_mended) {
  // A move may trade failing vertices for a pinched triangle (whose vertices failed already),
  // or put a facet far from ∂Ω on the boundary.
  std::vector<CellId> cells;
  for (const Move& m : moves) cells.push_back(m.cell);
  const std::size_t pinched_before = pinches_mended ? 0 : scan_.pinches_on(cells).size();
  std::vector<Label> old;
  for (const Move& m : moves)
    old.push_back(state_.output_label(m.cell)), state_.set_label(m.cell, m.to);
  const bool ok = (pinches_mended || scan_.pinches_on(cells).size() <= pinched_before) &&
                  new_boundary_near_surface(moves, old);
  for (std::size_t i = moves.size(); i-- > 0;) state_.set_label(moves[i].cell, old[i]);
  return ok;
}

std::vector<std::vector<ManifoldRelabeling::Move>> ManifoldRelabeling::options_at(
    const NonManifoldVertex& f, const std::vector<CellId>& star, int tier,
    const std::vector<VertexId>& focus) const {
  const auto& st = state_.tri.store();
  // Singles and pairs need a pentatope through the trouble (when the link shows where it is).
  const auto near_trouble = [&](CellId c) {
    if (focus.empty()) return true;
    for (VertexId u : st.cell(c).v)
      if (std::binary_search(focus.begin(), focus.end(), u)) return true;
    return false;
  };
  // The star sorted with positions: a neighbor's place in it by binary search.
  std::vector<std::pair<CellId, int>> index(star.size());
  for (std::size_t k = 0; k < star.size(); ++k) index[k] = {star[k], static_cast<int>(k)};
  std::sort(index.begin(), index.end());
  const auto in_star = [&](CellId c) {
    const auto it = std::lower_bound(index.begin(), index.end(), std::pair<CellId, int>{c, -1});
    return it != index.end() && it->first == c ? it->second : -1;
  };
  // Where each pentatope of the star would go: one of L to the most common other label among
  // its neighbors, any other to L when a neighbor has L; -1: nowhere.
  std::vector<int> to(star.size(), -1);
  for (std::size_t k = 0; k < star.size(); ++k) {
    const bool in = state_.output_label(star[k]) == f.label;
    std::array<std::pair<Label, int>, 5> votes{};
    int kinds = 0, best = 0;
    for (CellId n : st.cell(star[k]).n) {
      const Label l = state_.output_label(n);
      if (in ? l == f.label : l != f.label) continue;
      int i = 0;
      while (i < kinds && votes[i].first != l) ++i;
      if (i == kinds) votes[kinds++] = {l, 0};
      if (++votes[i].second > best) best = votes[i].second, to[k] = l;
    }
  }
  const auto move = [&](std::size_t k) { return Move{star[k], static_cast<Label>(to[k])}; };
  // The pieces of L and of the rest around f's vertex, joined through facets that contain it.
  support::UnionFind piece(star.size());
  if (tier >= 2)
    for (std::size_t k = 0; k < star.size(); ++k) {
      const auto& cell = st.cell(star[k]);
      const bool in = state_.output_label(star[k]) == f.label;
      for (int q = 0; q < 5; ++q) {
        if (cell.v[q] == f.vertex) continue;
        const int j = in_star(cell.n[q]);
        if (j >= 0 && (state_.output_label(cell.n[q]) == f.label) == in)
          piece.join(k, static_cast<std::size_t>(j));
      }
    }
  std::vector<std::vector<Move>> options;
  if (tier == 0) {
    for (std::size_t k = 0; k < star.size(); ++k)
      if (to[k] >= 0 && near_trouble(star[k])) options.push_back({move(k)});
  } else if (tier == 1) {
    for (std::size_t k = 0; k < star.size(); ++k) {
      if (to[k] < 0 || !near_trouble(star[k])) continue;
      for (CellId n : st.cell(star[k]).n) {
        const int j = in_star(n);
        if (j > static_cast<int>(k) && to[j] >= 0) options.push_back({move(k), move(j)});
      }
    }
  } else if (tier == 3) {
    // The part of the star the label keeps (or the rest keeps) is a ball grown from the largest
    // pieces of either side; what it leaves out changes side. A pentatope leaving L whose
    // neighbors are all L takes the star's most common other label.
    std::map<Label, int> others;
    for (CellId c : star)
      if (const Label l = state_.output_label(c); l != f.label) ++others[l];
    int fallback = -1, most = 0;
    for (const auto& [l, count] : others)
      if (count > most) most = count, fallback = l;
    for (const bool keep_label : {true, false}) {
      std::vector<char> side(star.size());
      std::map<std::size_t, std::size_t> sizes;
      for (std::size_t k = 0; k < star.size(); ++k)
        if ((side[k] = (state_.output_label(star[k]) == f.label) == keep_label))
          ++sizes[piece.find(k)];
      std::vector<std::pair<std::size_t, std::size_t>> seeds;  // (-size, root)
      for (const auto& [root, size] : sizes) seeds.push_back({star.size() - size, root});
      std::sort(seeds.begin(), seeds.end());
      if (seeds.size() > kBallSeeds) seeds.resize(kBallSeeds);
      for (const auto& [unused, root] : seeds) {
        const std::vector<char> ball = grow_link_ball(st, f.vertex, star, side, root);
        std::vector<Move> moves;
        for (std::size_t k = 0; k < star.size(); ++k) {
          if (!side[k] || ball[k]) continue;
          const int label = !keep_label ? f.label : to[k] >= 0 ? to[k] : fallback;
          if (label < 0 || moves.size() == kMaxBallMoves) {
            moves.clear();
            break;
          }
          moves.push_back({star[k], static_cast<Label>(label)});
        }
        if (!moves.empty()) options.push_back(std::move(moves));
      }
    }
  } else {
    std::map<std::size_t, std::vector<Move>> pieces;
    for (std::size_t k = 0; k < star.size(); ++k)
      if (to[k] >= 0) pieces[piece.find(k)].push_back(move(k));
    for (auto& [root, moves] : pieces)
      if (moves.size() > 2) options.push_back(std::move(moves));
  }
  return options;
}

void ManifoldRelabeling::apply(const std::vector<Move>& moves) {
  for (const Move& m : moves) {
    journal_.push_back({m.cell, state_.output_label(m.cell)});
    if (undo_log_) undo_log_->push_back(journal_.back());
    state_.set_label(m.cell, m.to);
    const auto& v = state_.tri.store().cell(m.cell).v;
    touched_.insert(touched_.end(), std::begin(v), std::end(v));
  }
}

void ManifoldRelabeling::undo_to(std::size_t journal_mark, std::size_t touched_mark) {
  while (journal_.size() > journal_mark) {
    state_.set_label(journal_.back().cell, journal_.back().to);
    journal_.pop_back();
  }
  touched_.resize(touched_mark);
}

bool ManifoldRelabeling::repair(const NonManifoldVertex& f, int depth, long* gained) {
  current_.clear();
  const std::vector<CellId> star = star_of(f.vertex);
  if (!region_link_fails(state_, f.vertex, star, f.label)) return false;  // an earlier move
  const std::vector<VertexId> focus = link_trouble(state_, f.vertex, star, f.label);
  // The cheapest tier that helps: most failures are one pentatope too many or too few.
  // Only options that mend f itself are weighed in full (one link instead of dozens).
  // Every option moves its pentatopes into or out of L, which flips whether each of their
  // link faces bounds L: f's new link is the old one xor those faces.
  std::vector<std::array<std::uint32_t, 3>> link, faces, after;
  std::size_t inside = 0;
  region_link(state_, f.vertex, star, f.label, link, &inside);
  std::sort(link.begin(), link.end());
  const auto mends_f = [&](const std::vector<Move>& option) {
    faces.clear();
    long change = 0;
    for (const Move& m : option) {
      const auto& cell = state_.tri.store().cell(m.cell);
      change += state_.output_label(m.cell) == f.label ? -1 : 1;
      for (int q = 0; q < 5; ++q) {
        if (cell.v[q] == f.vertex) continue;
        std::array<std::uint32_t, 3> t;
        for (int k = 0, n = 0; k < 5; ++k)
          if (k != q && cell.v[k] != f.vertex) t[n++] = cell.v[k];
        std::sort(t.begin(), t.end());
        faces.push_back(t);
      }
    }
    const long now = static_cast<long>(inside) + change;
    if (now == 0 || now == static_cast<long>(star.size())) return true;  // no boundary left at v
    std::sort(faces.begin(), faces.end());
    // A face shared by two moved pentatopes flips twice.
    std::size_t kept = 0;
    for (std::size_t i = 0; i < faces.size();)
      if (i + 1 < faces.size() && faces[i] == faces[i + 1]) {
        i += 2;
      } else {
        faces[kept++] = faces[i++];
      }
    faces.resize(kept);
    after.clear();
    std::set_symmetric_difference(link.begin(), link.end(), faces.begin(), faces.end(),
                                  std::back_inserter(after));
    return mesh::link_is_sphere(after);
  };
  // Options that mend f but break as many links elsewhere (or a few more): kept for a detour.
  std::vector<std::pair<long, std::vector<Move>>> detours;
  for (int tier = 0; tier < kTiers; ++tier) {
    auto options = options_at(f, star, tier, focus);
    // By gain, the largest first (the first listed among equals); the costlier checks (the
    // pinches, the new facets' distance to ∂Ω, which asks the oracle) only down that order.
    std::vector<std::pair<long, std::size_t>> ranked;
    for (std::size_t i = 0; i < options.size(); ++i)
      if (mends_f(options[i])) {
        const long gain = gain_of(options[i]);
        if (gain > 0) {
          ranked.push_back({-gain, i});
        } else if (depth > 0 && gain >= -kDetourLoss) {
          detours.push_back({-gain, options[i]});
        }
      }
    std::sort(ranked.begin(), ranked.end());
    for (const auto& [gain, i] : ranked)
      if (acceptable(options[i])) {
        *gained = -gain;
        apply(options[i]);
        return true;
      }
  }
  // A detour: the move that mends f, then the links it broke mended in turn (one level down);
  // kept when the whole lowers the count, undone otherwise.
  std::stable_sort(detours.begin(), detours.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  if (detours.size() > kDetours) detours.resize(kDetours);
  for (const auto& [loss, moves] : detours) {
    if (!acceptable(moves)) continue;
    const std::size_t journal_mark = journal_.size(), touched_mark = touched_.size();
    apply(moves);
    long total = -loss;
    std::vector<NonManifoldVertex> broken;
    std::vector<CellId> around;
    std::vector<VertexId> vertices(touched_.begin() + touched_mark, touched_.end());
    std::sort(vertices.begin(), vertices.end());
    vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());
    for (VertexId v : vertices) non_manifold_labels_at(state_, v, around, &broken);
    for (const NonManifoldVertex& b : broken) {
      long gain = 0;
      if (repair(b, depth - 1, &gain)) total += gain;
    }
    if (total > 0) {
      *gained = total;
      return true;
    }
    undo_to(journal_mark, touched_mark);
  }
  return false;
}

ManifoldRelabeling::Outcome ManifoldRelabeling::run(const std::vector<VertexId>* around) {
  Outcome outcome;
  std::vector<NonManifoldVertex> failing;
  if (around) {
    failing = failing_pairs_at(state_, *around);
  } else {
    failing = find_non_manifold_vertices(state_);
  }
  distinct_pairs(failing);
  std::vector<VertexId> retry;  // vertices near this round's moves
  for (int round = 0; round < kRounds && !failing.empty(); ++round) {
    std::size_t moved = 0;
    for (const NonManifoldVertex& f : failing)
      if (round == 0 || std::binary_search(retry.begin(), retry.end(), f.vertex)) {
        stars_.clear();
        journal_.clear();
        if (long gain = 0; repair(f, kDetourDepth, &gain)) moved += journal_.size();
      }
    outcome.moved += moved;
    // Only the moved pentatopes' vertices have new links: they and the failing ones are looked
    // at again, not the whole boundary. A pair that found no move is tried again only where a
    // move changed a star it reads (its vertex's star holds the moved pentatope's vertices).
    std::sort(touched_.begin(), touched_.end());
    touched_.erase(std::unique(touched_.begin(), touched_.end()), touched_.end());
    std::vector<VertexId> look = touched_;
    for (const NonManifoldVertex& f : failing) look.push_back(f.vertex);
    std::sort(look.begin(), look.end());
    look.erase(std::unique(look.begin(), look.end()), look.end());
    // (Read only: on the job's threads, each a contiguous share, joined in order.)
    const unsigned parts =
        support::parts_for(look.size(), kCheckShare, working_threads(state_.params));
    std::vector<std::vector<NonManifoldVertex>> found(parts);
    std::vector<std::vector<VertexId>> near(parts);
    support::run_parts(parts, [&](unsigned part) {
      std::vector<CellId> star;
      const auto [begin, end] = support::part_range(look.size(), part, parts);
      for (std::size_t i = begin; i < end; ++i) {
        const VertexId v = look[i];
        non_manifold_labels_at(state_, v, star, &found[part]);
        if (std::binary_search(touched_.begin(), touched_.end(), v))
          for (CellId c : star)
            for (VertexId u : state_.tri.store().cell(c).v) near[part].push_back(u);
      }
    });
    failing.clear();
    retry.clear();
    for (unsigned part = 0; part < parts; ++part) {
      failing.insert(failing.end(), found[part].begin(), found[part].end());
      retry.insert(retry.end(), near[part].begin(), near[part].end());
    }
    distinct_pairs(failing);
    std::sort(retry.begin(), retry.end());
    retry.erase(std::unique(retry.begin(), retry.end()), retry.end());
    touched_.clear();
    if (moved == 0) break;
  }
  stars_.clear();
  near_facets_.clear();
  outcome.failing = std::move(failing);
  return outcome;
}

}  // namespace mesh4d::refine
