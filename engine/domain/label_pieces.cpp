#include "domain/label_pieces.h"

#include <algorithm>
#include <array>

#include "domain/surface_oracle.h"
#include "support/union_find.h"

namespace mesh4d::domain {

namespace {

// The face-connected pieces of the non-zero labels only (the background, most of a heart image,
// is never flooded).
FacePieces foreground_face_pieces(const LabelImage4& image) {
  const auto& d = image.dims();
  FacePieces out;
  out.piece.assign(image.voxel_count(), FacePieces::kNoPiece);
  std::vector<std::size_t> frontier;
  for (std::size_t seed = 0; seed < image.voxel_count(); ++seed) {
    if (image.at(seed) == 0 || out.piece[seed] != FacePieces::kNoPiece) continue;
    const auto id = static_cast<std::uint32_t>(out.pieces.size());
    FacePieces::Piece p;
    p.label = image.at(seed);
    out.piece[seed] = id;
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const std::size_t i = frontier.back();
      frontier.pop_back();
      ++p.voxels;
      const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / (d[0] * d[1]) % d[2],
                                i / (d[0] * d[1] * d[2])};
      for (int a = 0; a < 4; ++a) p.touches_border |= c[a] == 0 || c[a] + 1 == d[a];
      for_each_face_neighbor(image, i, [&](std::size_t j) {
        if (out.piece[j] == FacePieces::kNoPiece && image.at(j) == p.label) {
          out.piece[j] = id;
          frontier.push_back(j);
        }
      });
    }
    out.pieces.push_back(p);
  }
  return out;
}

}  // namespace

FacePieces label_function_pieces(const LabelImage4& image) {
  FacePieces face = foreground_face_pieces(image);
  if (face.pieces.empty()) return face;
  const auto& d = image.dims();
  const std::vector<double> beta = SurfaceOracle::label_offsets(image.labels());
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  // Only blocks with a foreground voxel can join anything: the foreground's bounding box.
  std::array<std::size_t, 4> lo = d, hi{};
  for (std::size_t i = 0; i < image.voxel_count(); ++i) {
    if (image.at(i) == 0) continue;
    const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / (d[0] * d[1]) % d[2],
                              i / (d[0] * d[1] * d[2])};
    for (int a = 0; a < 4; ++a) lo[a] = std::min(lo[a], c[a]), hi[a] = std::max(hi[a], c[a]);
  }
  support::UnionFind joined(face.pieces.size());
  std::size_t c[4];
  for (c[3] = lo[3] ? lo[3] - 1 : 0; c[3] <= hi[3]; ++c[3])
    for (c[2] = lo[2] ? lo[2] - 1 : 0; c[2] <= hi[2]; ++c[2])
      for (c[1] = lo[1] ? lo[1] - 1 : 0; c[1] <= hi[1]; ++c[1])
        for (c[0] = lo[0] ? lo[0] - 1 : 0; c[0] <= hi[0]; ++c[0]) {
          const std::size_t origin = c[0] + c[1] * stride[1] + c[2] * stride[2] + c[3] * stride[3];
          // The axes along which the block may extend, and its voxels' labels (corner bit a:
          // +1 along axis a).
          int axes = 0;
          for (int a = 0; a < 4; ++a)
            if (c[a] + 1 < d[a]) axes |= 1 << a;
          std::array<Label, 16> label{};
          bool uniform = true;
          for (int corner = 0; corner < 16; ++corner) {
            if (corner & ~axes) continue;
            std::size_t i = origin;
            for (int a = 0; a < 4; ++a)
              if (corner >> a & 1) i += stride[a];
            label[corner] = image.at(i);
            uniform = uniform && label[corner] == label[0];
          }
          if (uniform) continue;
          // Every block through the origin spanning two or more axes.
          for (int span = 3; span < 16; ++span) {
            if ((span & ~axes) || __builtin_popcount(span) < 2) continue;
            // The label of the block's center: the most voxels, ties to the larger β.
            std::array<std::pair<Label, int>, 16> counts;
            int kinds = 0;
            for (int corner = 0; corner < 16; ++corner) {
              if (corner & ~span) continue;
              int k = 0;
              while (k < kinds && counts[k].first != label[corner]) ++k;
              if (k == kinds) counts[kinds++] = {label[corner], 0};
              ++counts[k].second;
            }
            Label center = 0;
            double best = -1;
            for (int k = 0; k < kinds; ++k) {
              const auto [l, n] = counts[k];
              const double value = n + beta[l] * (1 << __builtin_popcount(span));
              if (value > best || (value == best && l < center)) best = value, center = l;
            }
            if (center == 0) continue;
            // Opposite corners (each pair once: the one holding the span's lowest axis).
            for (int corner = 0; corner < 16; ++corner) {
              if ((corner & ~span) || !(corner & span & -span)) continue;
              const int opposite = span & ~corner;
              if (label[corner] != center || label[opposite] != center) continue;
              std::size_t i = origin, j = origin;
              for (int a = 0; a < 4; ++a) {
                if (corner >> a & 1) i += stride[a];
                if (opposite >> a & 1) j += stride[a];
              }
              joined.join(face.piece[i], face.piece[j]);
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

}  // namespace mesh4d::domain
