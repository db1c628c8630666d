#include "domain/diagonal_fill.h"

#include <algorithm>
#include <array>
#include <unordered_map>
#include <vector>

#include "domain/face_components.h"
#include "domain/label_pieces.h"

namespace mesh4d::domain {
namespace {

// Rounds of fills (each on the face pieces as the last left them): a fill can bring another
// contact's block a voxel of its label, and so a join, that was not there before.
constexpr int kRounds = 4;

using Coords = std::array<long, 4>;

Coords coords_of(const LabelImage4& image, std::size_t i) {
  const auto& d = image.dims();
  return {long(i % d[0]), long(i / d[0] % d[1]), long(i / (d[0] * d[1]) % d[2]),
          long(i / (d[0] * d[1] * d[2]))};
}

std::size_t index_of(const LabelImage4& image, const Coords& c) {
  return image.linear_index(std::size_t(c[0]), std::size_t(c[1]), std::size_t(c[2]),
                            std::size_t(c[3]));
}

// Whether voxel k may take another label: its face neighbors with its label (as `label_at`
// reads them) stay face-connected to each other through voxels of that label in the 3⁴ voxels
// around k, without k.
template <class LabelAt>
bool keeps_its_label_connected(const LabelImage4& image, std::size_t k, LabelAt&& label_at) {
  const Label m = label_at(k);
  const Coords c = coords_of(image, k);
  const auto& d = image.dims();
  // The window's voxels by offset code (digits in base 3, less one), and k's own code (40).
  std::array<int, 81> in{};  // 1: voxel of m in the window
  for (int code = 0; code < 81; ++code) {
    Coords v = c;
    bool inside = true;
    for (int a = 0, rest = code; a < 4; ++a, rest /= 3) {
      v[a] += rest % 3 - 1;
      inside = inside && v[a] >= 0 && v[a] < long(d[a]);
    }
    in[code] = code != 40 && inside && label_at(index_of(image, v)) == m;
  }
  constexpr int kPow[4] = {1, 3, 9, 27};
  std::array<int, 81> seen{};
  int start = -1, targets = 0;
  for (int a = 0; a < 4; ++a)
    for (int s : {-1, 1})
      if (const int n = 40 + s * kPow[a]; in[n]) {
        ++targets;
        if (start < 0) start = n;
      }
  if (targets <= 1) return true;
  std::vector<int> frontier{start};
  seen[start] = 1;
  int reached = 0;
  while (!frontier.empty()) {
    const int u = frontier.back();
    frontier.pop_back();
    for (int a = 0; a < 4; ++a)
      if (u == 40 + kPow[a] || u == 40 - kPow[a]) ++reached;
    for (int a = 0; a < 4; ++a) {
      const int digit = u / kPow[a] % 3;
      for (int s : {-1, 1}) {
        if (digit + s < 0 || digit + s > 2) continue;
        const int n = u + s * kPow[a];
        if (in[n] && !seen[n]) seen[n] = 1, frontier.push_back(n);
      }
    }
  }
  return reached == targets;
}

}  // namespace

DiagonalFill fill_diagonal_joins(LabelImage4& image, unsigned threads) {
  DiagonalFill out;
  bool settled = false;  // a round found every join a face join already
  for (int round = 0; round < kRounds && !settled; ++round) {
    const FacePieces face = face_pieces(image, false, threads);
    if (face.pieces.empty()) return out;
    // The labels the fills give, applied when the round's walk is over (the walk reads the
    // image as it was); the checks read them.
    std::unordered_map<std::size_t, Label> fills;
    const auto label_at = [&](std::size_t v) {
      const auto it = fills.find(v);
      return it == fills.end() ? image.at(v) : it->second;
    };
    std::size_t joins = 0;
    for_each_diagonal_join(image, face, [&](std::size_t i, std::size_t j) {
      ++joins;
      const Label l = image.at(i);
      const Coords ci = coords_of(image, i), cj = coords_of(image, j);
      std::array<int, 4> axes{};
      int n = 0;
      for (int a = 0; a < 4; ++a)
        if (ci[a] != cj[a]) axes[n++] = a;
      // Every face path from i to j through the block (one axis at a time, in each order):
      // the one with the fewest voxels to change, each allowed to change.
      std::vector<std::size_t> best;
      bool found = false;
      do {
        std::vector<std::size_t> change;
        Coords v = ci;
        bool ok = true;
        for (int s = 0; s + 1 < n && ok; ++s) {
          v[axes[s]] = cj[axes[s]];
          const std::size_t k = index_of(image, v);
          if (label_at(k) == l) continue;
          ok = keeps_its_label_connected(image, k, label_at);
          change.push_back(k);
        }
        if (ok && (!found || change.size() < best.size())) best = change, found = true;
      } while (std::next_permutation(axes.begin(), axes.begin() + n));
      if (!found) return false;
      for (std::size_t k : best) fills[k] = l;
      DiagonalFill::PerLabel& per = out.labels[l];
      ++per.contacts;
      per.voxels += best.size();
      return true;
    });
    settled = joins == 0;
    if (fills.empty()) break;
    for (const auto& [k, l] : fills) image.set(k, l);
  }
  // What no path could fill.
  if (!settled)
    for_each_diagonal_join(image, face_pieces(image, false, threads),
                           [&](std::size_t i, std::size_t) {
                             ++out.labels[image.at(i)].left;
                             return true;
                           });
  return out;
}

}  // namespace mesh4d::domain
