#include "domain/uniform_cells.h"

#include <algorithm>

#include "support/parallel_parts.h"

namespace mesh4d::domain {

namespace {

constexpr std::size_t kMinShare = std::size_t{1} << 16;  // voxels per thread, at least

}  // namespace

UniformCells::UniformCells(const LabelImage4& image, unsigned threads) {
  // Separably, one axis at a time: same[i] says whether every corner of the cell's face spanned
  // by the axes done so far, lowest corner i, has the label of voxel i. A cell reaching past
  // the last voxel along an axis is never uniform (its outer corners are background).
  const Dims4& d = image.dims();
  const std::size_t n = image.voxel_count();
  std::vector<std::uint8_t> same(n, 1);
  const unsigned parts = support::parts_for(n, kMinShare, threads);
  std::size_t stride = 1;
  for (int axis = 0; axis < 4; ++axis) {
    const std::size_t length = d[axis];
    const std::size_t layers = n / (stride * length);
    // A chain of voxels along the axis (one layer, one offset k in it) reads only itself, in
    // increasing i, so that same[i + stride] still holds the previous axis' answer: the chains
    // are split among the threads, by layers where there are enough, else by offsets.
    const auto pass = [&](std::size_t first_layer, std::size_t end_layer, std::size_t first_k,
                          std::size_t end_k) {
      for (std::size_t layer = first_layer; layer < end_layer; ++layer)
        for (std::size_t along = 0; along < length; ++along) {
          const std::size_t base = (layer * length + along) * stride;
          for (std::size_t k = first_k; k < end_k; ++k) {
            const std::size_t i = base + k;
            same[i] = same[i] && along + 1 < length && same[i + stride] &&
                      image.at(i + stride) == image.at(i);
          }
        }
    };
    support::run_parts(parts, [&](unsigned part) {
      if (layers >= parts) {
        const auto [begin, end] = support::part_range(layers, part, parts);
        pass(begin, end, 0, stride);
      } else {
        const auto [begin, end] = support::part_range(stride, part, parts);
        pass(0, layers, begin, end);
      }
    });
    stride *= length;
  }
  bits_.assign((n + 63) / 64, 0);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(bits_.size(), part, parts);
    for (std::size_t w = begin; w < end; ++w)
      for (std::size_t i = 64 * w; i < std::min(n, 64 * w + 64); ++i)
        if (same[i]) bits_[w] |= std::uint64_t(1) << (i & 63);
  });
}

}  // namespace mesh4d::domain
