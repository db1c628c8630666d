#include "domain/uniform_cells.h"

namespace mesh4d::domain {

UniformCells::UniformCells(const LabelImage4& image) {
  // Separably, one axis at a time: same[i] says whether every corner of the cell's face spanned
  // by the axes done so far, lowest corner i, has the label of voxel i. A cell reaching past
  // the last voxel along an axis is never uniform (its outer corners are background).
  const Dims4& d = image.dims();
  const std::size_t n = image.voxel_count();
  std::vector<std::uint8_t> same(n, 1);
  std::size_t stride = 1;
  for (int axis = 0; axis < 4; ++axis) {
    // In increasing i, so that same[i + stride] still holds the previous axis' answer.
    const std::size_t layers = n / (stride * d[axis]);
    for (std::size_t i = 0, layer = 0; layer < layers; ++layer)
      for (std::size_t along = 0; along < d[axis]; ++along)
        for (std::size_t k = 0; k < stride; ++k, ++i)
          same[i] = same[i] && along + 1 < d[axis] && same[i + stride] &&
                    image.at(i + stride) == image.at(i);
    stride *= d[axis];
  }
  bits_.assign((n + 63) / 64, 0);
  for (std::size_t i = 0; i < n; ++i)
    if (same[i]) bits_[i >> 6] |= std::uint64_t(1) << (i & 63);
}

}  // namespace mesh4d::domain
