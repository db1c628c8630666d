#include "domain/face_components.h"

#include <algorithm>

#include "support/parallel_parts.h"
#include "support/union_find.h"

namespace mesh4d::domain {
namespace {

// Fewer voxels than this a slab are flooded on one thread.
constexpr std::size_t kMinSlabVoxels = std::size_t{1} << 20;

// Floods the pieces of voxels [begin, end) (whole layers along the last axis), seeds in index
// order, without crossing out of the range: their voxels get ids first_id, first_id + 1, ...
// in `piece`, and their records go to `out`.
void flood(const LabelImage4& image, bool with_background, std::size_t begin, std::size_t end,
           std::uint32_t first_id, std::vector<std::uint32_t>& piece,
           std::vector<FacePieces::Piece>& out) {
  const auto& d = image.dims();
  const std::size_t stride[4] = {1, d[0], d[0] * d[1], d[0] * d[1] * d[2]};
  std::vector<std::size_t> frontier;
  for (std::size_t seed = begin; seed < end; ++seed) {
    if (piece[seed] != FacePieces::kNoPiece || (!with_background && image.at(seed) == 0)) continue;
    const auto id = static_cast<std::uint32_t>(first_id + out.size());
    FacePieces::Piece p;
    p.label = image.at(seed);
    piece[seed] = id;
    frontier.assign(1, seed);
    while (!frontier.empty()) {
      const std::size_t i = frontier.back();
      frontier.pop_back();
      ++p.voxels;
      // The coordinates once per voxel: the neighbors by strides.
      const std::size_t c[4] = {i % d[0], i / d[0] % d[1], i / stride[2] % d[2], i / stride[3]};
      const auto visit = [&](std::size_t j) {
        if (piece[j] == FacePieces::kNoPiece && image.at(j) == p.label) {
          piece[j] = id;
          frontier.push_back(j);
        }
      };
      for (int a = 0; a < 4; ++a) {
        p.touches_border |= c[a] == 0 || c[a] + 1 == d[a];
        // The range holds whole frames: only a step along t can leave it.
        if (c[a] > 0 && (a < 3 || i - stride[a] >= begin)) visit(i - stride[a]);
        if (c[a] + 1 < d[a] && (a < 3 || i + stride[a] < end)) visit(i + stride[a]);
      }
    }
    out.push_back(p);
  }
}

}  // namespace

FacePieces face_pieces(const LabelImage4& image, bool with_background, unsigned threads) {
  const auto& d = image.dims();
  const std::size_t layer = d[0] * d[1] * d[2];  // voxels of one time frame
  const std::size_t n = image.voxel_count();
  FacePieces out;
  out.piece.assign(n, FacePieces::kNoPiece);
  const unsigned slabs = support::parts_for(std::min(n / kMinSlabVoxels, d[3]), 1, threads);
  constexpr std::uint32_t kSlabIds = 1u << 27;  // ids of slab s start at s · kSlabIds
  if (slabs == 1 || n / slabs >= kSlabIds) {
    flood(image, with_background, 0, n, 0, out.piece, out.pieces);
    return out;
  }
  // Slabs of whole frames flooded side by side, ids apart by slab; then the pieces that meet
  // across a slab's first frame joined, and renumbered in the order of their first voxel (each
  // slab's pieces are in that order already, and a joined piece's first voxel is its first
  // slab's seed), as one flood over the whole image numbers them.
  std::vector<std::size_t> first_frame(slabs + 1);
  for (unsigned s = 0; s <= slabs; ++s) first_frame[s] = support::part_range(d[3], s, slabs).first;
  std::vector<std::vector<FacePieces::Piece>> local(slabs);
  support::run_parts(slabs, [&](unsigned s) {
    flood(image, with_background, first_frame[s] * layer, first_frame[s + 1] * layer, s * kSlabIds,
          out.piece, local[s]);
  });
  std::vector<std::size_t> offset(slabs + 1, 0);  // each slab's first piece in one numbering
  for (unsigned s = 0; s < slabs; ++s) offset[s + 1] = offset[s] + local[s].size();
  const auto global = [&](std::uint32_t id) { return offset[id / kSlabIds] + id % kSlabIds; };
  support::UnionFind joined(offset[slabs]);
  for (unsigned s = 1; s < slabs; ++s) {
    const std::size_t start = first_frame[s] * layer;
    for (std::size_t i = start; i < start + layer; ++i) {
      const std::uint32_t here = out.piece[i], below = out.piece[i - layer];
      if (here != FacePieces::kNoPiece && below != FacePieces::kNoPiece &&
          image.at(i) == image.at(i - layer))
        joined.join(global(below), global(here));
    }
  }
  // Numbered in slab order, each class at its first member: the order of first voxels.
  std::vector<std::uint32_t> id(offset[slabs], FacePieces::kNoPiece);
  std::vector<std::uint32_t> class_id(offset[slabs], FacePieces::kNoPiece);
  for (unsigned s = 0; s < slabs; ++s)
    for (std::size_t k = 0; k < local[s].size(); ++k) {
      const std::size_t g = offset[s] + k;
      std::uint32_t& c = class_id[joined.find(g)];
      const FacePieces::Piece& p = local[s][k];
      if (c == FacePieces::kNoPiece) {
        c = static_cast<std::uint32_t>(out.pieces.size());
        out.pieces.push_back(p);
      } else {
        out.pieces[c].voxels += p.voxels;
        out.pieces[c].touches_border |= p.touches_border;
      }
      id[g] = c;
    }
  support::run_parts(slabs, [&](unsigned s) {
    for (std::size_t i = first_frame[s] * layer; i < first_frame[s + 1] * layer; ++i)
      if (out.piece[i] != FacePieces::kNoPiece) out.piece[i] = id[global(out.piece[i])];
  });
  return out;
}

}  // namespace mesh4d::domain
