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

}  // namespace

FacePieces label_function_pieces(const LabelImage4& image,
                                 std::vector<FacePieces::Piece>* face_out) {
  // The foreground's pieces (the background, most of a heart image, is never flooded).
  FacePieces face = face_pieces(image, false);
  if (face.pieces.empty()) return face;
  const auto& d = image.dims();
  // Only blocks with a foreground voxel can join anything: the foreground's bounding box.
  std::array<std::size_t, 4> lo = d, hi{};
  bool background = false;
  {
    std::size_t c[4], i = 0;
    for (c[3] = 0; c[3] < d[3]; ++c[3])
      for (c[2] = 0; c[2] < d[2]; ++c[2])
        for (c[1] = 0; c[1] < d[1]; ++c[1])
          for (c[0] = 0; c[0] < d[0]; ++c[0], ++i) {
            if (face.piece[i] == FacePieces::kNoPiece) {
              background = true;
              continue;
            }
            for (int a = 0; a < 4; ++a)
              lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
          }
  }
  // The labels present, as LabelImage4::labels() lists them (without another pass).
  std::vector<Label> labels;
  if (background) labels.push_back(0);
  for (const FacePieces::Piece& p : face.pieces) labels.push_back(p.label);
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  const std::vector<double> beta = SurfaceOracle::label_offsets(labels);
  if (face_out) *face_out = face.pieces;
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  std::size_t c[4];
  // Each block's corner k (bit a: +1 along axis a) at origin + offset[k].
  std::array<std::size_t, 16> offset{};
  for (int k = 0; k < 16; ++k)
    for (int a = 0; a < 4; ++a)
      if (k >> a & 1) offset[k] += stride[a];
  support::UnionFind joined(face.pieces.size());
  for (c[3] = lo[3] ? lo[3] - 1 : 0; c[3] <= hi[3]; ++c[3])
    for (c[2] = lo[2] ? lo[2] - 1 : 0; c[2] <= hi[2]; ++c[2])
      for (c[1] = lo[1] ? lo[1] - 1 : 0; c[1] <= hi[1]; ++c[1]) {
        // The axes along which blocks at this row's origins may extend.
        int row_axes = 0;
        for (int a = 1; a < 4; ++a)
          if (c[a] + 1 < d[a]) row_axes |= 1 << a;
        const std::size_t row = c[1] * stride[1] + c[2] * stride[2] + c[3] * stride[3];
        for (c[0] = lo[0] ? lo[0] - 1 : 0; c[0] <= hi[0]; ++c[0]) {
          const int axes = row_axes | (c[0] + 1 < d[0] ? 1 : 0);
          const std::size_t origin = row + c[0];
          std::array<Label, 16> label{};
          bool uniform = true;
          const Label first = image.at(origin);
          for (int k = 1; k < 16; ++k) {
            if (k & ~axes) continue;
            label[k] = image.at(origin + offset[k]);
            uniform = uniform && label[k] == first;
          }
          label[0] = first;
          if (uniform) continue;
          // Every block through the origin spanning two or more axes, where two opposite
          // corners hold one label in pieces not yet joined: whether the block's center has it.
          for (int span = 3; span < 16; ++span) {
            if ((span & ~axes) || kBits[span] < 2) continue;
            int center = -1;  // not yet known
            for (int k = 0; k < 16; ++k) {
              // Each pair once: the corner holding the span's lowest axis.
              if ((k & ~span) || !(k & span & -span)) continue;
              const int opposite = span & ~k;
              if (label[k] == 0 || label[k] != label[opposite]) continue;
              const std::size_t a = face.piece[origin + offset[k]];
              const std::size_t b = face.piece[origin + offset[opposite]];
              if (a == b || joined.find(a) == joined.find(b)) continue;
              if (center < 0) center = center_label(label, span, beta);
              if (center == label[k]) joined.join(a, b);
            }
          }
        }
      }
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
    if (axes == 0 || !inside || image.at(std::size_t(j)) != l) continue;
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

}  // namespace mesh4d::domain
