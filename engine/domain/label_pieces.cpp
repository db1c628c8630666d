#include "domain/label_pieces.h"

#include <algorithm>
#include <array>

#include "domain/surface_oracle.h"
#include "support/union_find.h"

namespace mesh4d::domain {

namespace {

// Set bits of 0..15.
constexpr int kBits[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};

// The label the label function gives the center of the block of corners in `span` (bit a: the
// block extends along axis a): the most voxels, ties to the larger offset β.
Label center_label(const std::array<Label, 16>& label, int span, const std::vector<double>& beta) {
  std::array<std::pair<Label, int>, 16> counts;
  int kinds = 0;
  for (int k = 0; k < 16; ++k) {
    if (k & ~span) continue;
    int q = 0;
    while (q < kinds && counts[q].first != label[k]) ++q;
    if (q == kinds) counts[kinds++] = {label[k], 0};
    ++counts[q].second;
  }
  Label center = 0;
  double best = -1;
  const int voxels = 1 << kBits[span];
  for (int q = 0; q < kinds; ++q) {
    const auto [l, n] = counts[q];
    const double value = n + beta[l] * voxels;
    if (value > best || (value == best && l < center)) best = value, center = l;
  }
  return center;
}

// Calls fn(j) for every neighbor j of voxel i (offsets in {-1, 0, 1}⁴ along `min_axes` or more
// axes) that has i's non-zero label, for which wanted(j) holds and, when it is diagonal, whose
// block's center the label function gives to that label.
template <class Wanted, class Fn>
void for_each_joined(const LabelImage4& image, const std::vector<double>& beta, std::size_t i,
                     int min_axes, Wanted&& wanted, Fn&& fn) {
  const auto& d = image.dims();
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  const long c[4] = {long(i % d[0]), long(i / d[0] % d[1]), long(i / stride[2] % d[2]),
                     long(i / stride[3])};
  const Label l = image.at(i);
  // Every offset in {-1, 0, 1}⁴ but 0 (step: its digits in base 3, less one).
  for (int code = 0; code < 81; ++code) {
    int step[4], axes = 0;
    bool inside = true;
    long j = long(i);
    for (int a = 0, rest = code; a < 4; ++a, rest /= 3) {
      step[a] = rest % 3 - 1;
      if (step[a] == 0) continue;
      axes |= 1 << a;
      inside = inside && c[a] + step[a] >= 0 && c[a] + step[a] < long(d[a]);
      j += step[a] * long(stride[a]);
    }
    if (kBits[axes] < min_axes || !inside || image.at(std::size_t(j)) != l ||
        !wanted(std::size_t(j)))
      continue;
    if (kBits[axes] == 1) {
      fn(std::size_t(j));
      continue;
    }
    // The block between i and j, corner k taking the step along the axes of k.
    std::array<Label, 16> label{};
    for (int k = 0; k < 16; ++k) {
      if (k & ~axes) continue;
      long v = long(i);
      for (int a = 0; a < 4; ++a)
        if (k >> a & 1) v += step[a] * long(stride[a]);
      label[k] = image.at(std::size_t(v));
    }
    if (center_label(label, axes, beta) == l) fn(std::size_t(j));
  }
}

}  // namespace

void for_each_diagonal_join(const LabelImage4& image, const FacePieces& face,
                            const std::function<bool(std::size_t, std::size_t)>& fn) {
  // The labels present, as LabelImage4::labels() lists them (without another pass), and each
  // label's largest piece.
  std::vector<Label> labels;
  std::size_t foreground = 0;
  std::vector<std::uint32_t> largest(std::size_t{1} << 16, FacePieces::kNoPiece);  // by label
  for (std::size_t p = 0; p < face.pieces.size(); ++p) {
    const FacePieces::Piece& piece = face.pieces[p];
    labels.push_back(piece.label);
    foreground += piece.voxels;
    std::uint32_t& big = largest[piece.label];
    if (big == FacePieces::kNoPiece || face.pieces[big].voxels < piece.voxels)
      big = static_cast<std::uint32_t>(p);
  }
  if (foreground < image.voxel_count()) labels.push_back(0);
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const std::vector<double> beta = SurfaceOracle::label_offsets(labels);
  // Two pieces of a label that meet diagonally are never both its largest: only the other
  // pieces' voxels (on the patients a few thousand of millions) look for diagonal neighbors
  // in another piece not yet joined to theirs.
  support::UnionFind joined(face.pieces.size());
  for (std::size_t i = 0; i < face.piece.size(); ++i) {
    const std::uint32_t p = face.piece[i];
    if (p == FacePieces::kNoPiece || p == largest[face.pieces[p].label]) continue;
    for_each_joined(
        image, beta, i, 2,
        [&](std::size_t j) { return joined.find(face.piece[j]) != joined.find(p); },
        [&](std::size_t j) {
          if (fn(i, j)) joined.join(face.piece[j], p);
        });
  }
}

FacePieces label_function_pieces(const LabelImage4& image, std::vector<FacePieces::Piece>* face_out,
                                 unsigned threads) {
  // The foreground's pieces (the background, most of a heart image, is never flooded).
  FacePieces face = face_pieces(image, false, threads);
  if (face.pieces.empty()) return face;
  if (face_out) *face_out = face.pieces;
  support::UnionFind joined(face.pieces.size());
  for_each_diagonal_join(image, face, [&](std::size_t i, std::size_t j) {
    joined.join(face.piece[i], face.piece[j]);
    return true;
  });
  // Renumbered by the first voxel of each joined piece.
  FacePieces out;
  std::vector<std::uint32_t> id(face.pieces.size(), FacePieces::kNoPiece);
  for (std::size_t p = 0; p < face.pieces.size(); ++p) {
    std::uint32_t& root = id[joined.find(p)];
    if (root == FacePieces::kNoPiece) {
      root = static_cast<std::uint32_t>(out.pieces.size());
      out.pieces.push_back({face.pieces[p].label, 0, false});
    }
    out.pieces[root].voxels += face.pieces[p].voxels;
    out.pieces[root].touches_border |= face.pieces[p].touches_border;
  }
  out.piece = std::move(face.piece);
  for (std::uint32_t& p : out.piece)
    if (p != FacePieces::kNoPiece) p = id[joined.find(p)];
  return out;
}

void for_each_joined_neighbor(const LabelImage4& image, const std::vector<double>& beta,
                              std::size_t i, const std::function<void(std::size_t)>& fn) {
  for_each_joined(
      image, beta, i, 1, [](std::size_t) { return true; }, fn);
}

}  // namespace mesh4d::domain
