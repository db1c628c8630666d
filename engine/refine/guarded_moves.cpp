#include "refine/guarded_moves.h"

#include "delaunay/geometry.h"
#include "delaunay/predicates.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

namespace {

constexpr std::size_t kMinShare = 4096;  // pentatopes per thread, at least
constexpr int kHalvings = 4;             // then a move that still spoils a pentatope is dropped

// Whether a pentatope with corners moved is still as good as the refinement left it: positively
// oriented (exactly), no sliver it was not, and no radius-edge ratio past the bound it was not.
struct Quality {
  double tau = 0, rho = 0;  // normalized volume, radius-edge ratio
};

Quality quality(const delaunay::Simplex4& s) {
  const double r = delaunay::circumradius(s);
  return {delaunay::normalized_volume(s, r), r / delaunay::shortest_edge(s)};
}

// `before` is asked only where the moved pentatope is past a bound: most are not.
template <class Before>
bool still_good(const Before& before, const delaunay::Simplex4& after, const RefineParams& params) {
  if (delaunay::orient4(after[0], after[1], after[2], after[3], after[4]) <= 0) return false;
  const Quality now = quality(after);
  if (now.tau < params.sliver_bound && now.tau < before().tau) return false;
  return now.rho < params.radius_edge_bound || now.rho <= before().rho;
}

}  // namespace

GuardedMoves move_guarded(mesh::Mesh4& mesh, const std::vector<Point4>& before,
                          const std::vector<std::uint32_t>& glued,
                          const std::vector<Point4>& offset,
                          const std::vector<std::uint32_t>& moving,
                          const std::function<bool(std::uint32_t pentatope)>& counts,
                          const RefineParams& params) {
  const std::size_t nv = mesh.vertices.size();
  const unsigned threads = working_threads(params);
  // The pentatopes a move touches, and the moves' scales, halved where one spoils a pentatope.
  std::vector<double> scale(nv, 0);
  for (std::uint32_t v : moving) scale[v] = 1;
  // The pentatopes of `among` (all when null) with a corner that `moves`, in order: each part
  // of them on a thread, joined in part order.
  const auto those_with = [&](const std::vector<std::uint32_t>* among, const auto& moves) {
    const std::size_t n = among ? among->size() : mesh.pentatopes.size();
    const unsigned parts = support::parts_for(n, kMinShare, threads);
    std::vector<std::vector<std::uint32_t>> found(parts);
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(n, part, parts);
      for (std::size_t i = begin; i < end; ++i) {
        const std::uint32_t p = among ? (*among)[i] : static_cast<std::uint32_t>(i);
        for (std::uint32_t v : mesh.pentatopes[p])
          if (moves(glued[v], p)) {
            found[part].push_back(static_cast<std::uint32_t>(i));
            break;
          }
      }
    });
    std::vector<std::uint32_t> out;
    for (const auto& f : found) out.insert(out.end(), f.begin(), f.end());
    return out;
  };
  const std::vector<std::uint32_t> touched = those_with(
      nullptr,
      [&](std::uint32_t g, std::uint32_t p) { return scale[g] > 0 && (!counts || counts(p)); });
  const auto place = [&] {
    const unsigned parts = support::parts_for(nv, kMinShare, threads);
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(nv, part, parts);
      for (std::size_t v = begin; v < end; ++v) {
        const double k = scale[glued[v]];
        for (int a = 0; a < 4; ++a) mesh.vertices[v][a] = before[v][a] + k * offset[glued[v]][a];
      }
    });
  };
  // Each round checks the pentatopes whose corners moved differently in the last one.
  std::vector<Quality> was(touched.size());
  std::vector<char> known(touched.size(), 0), spoiled(touched.size()), changed(nv, 1);
  std::vector<std::uint32_t> check(touched.size());
  for (std::uint32_t i = 0; i < touched.size(); ++i) check[i] = i;
  for (int round = 0; !check.empty(); ++round) {
    place();
    const unsigned check_parts = support::parts_for(check.size(), kMinShare, threads);
    support::run_parts(check_parts, [&](unsigned p) {
      const auto [begin, end] = support::part_range(check.size(), p, check_parts);
      for (std::size_t c = begin; c < end; ++c) {
        const std::uint32_t i = check[c];
        delaunay::Simplex4 is;
        for (int k = 0; k < 5; ++k) {
          const std::uint32_t v = mesh.pentatopes[touched[i]][k];
          is[k] = mesh.vertices[v];
        }
        const auto original = [&]() -> const Quality& {
          if (!known[i]) {
            delaunay::Simplex4 corners;
            for (int k = 0; k < 5; ++k) corners[k] = before[mesh.pentatopes[touched[i]][k]];
            was[i] = quality(corners);
            known[i] = 1;
          }
          return was[i];
        };
        spoiled[i] = !still_good(original, is, params);
      }
    });
    std::fill(changed.begin(), changed.end(), 0);
    for (std::uint32_t i : check) {
      if (!spoiled[i]) continue;
      for (std::uint32_t v : mesh.pentatopes[touched[i]]) {
        double& k = scale[glued[v]];
        if (k == 0) continue;
        k = round < kHalvings ? k / 2 : 0;
        changed[glued[v]] = 1;
      }
    }
    check = those_with(&touched, [&](std::uint32_t g, std::uint32_t) { return changed[g] != 0; });
  }
  return {std::move(scale)};
}

}  // namespace mesh4d::refine
