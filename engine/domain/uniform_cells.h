// Which voxel cells have one label at all 16 corners: there the label function is that label
// everywhere in the cell, with no interpolation to do. The crossing walks and the labels at
// circumcenters mostly land in such cells, and one bit read there replaces 16 scattered label
// reads (the surface oracle's largest cost).
#pragma once

#include <cstdint>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

class UniformCells {
 public:
  /// Found on `threads` threads (the same cells with any number).
  explicit UniformCells(const LabelImage4& image, unsigned threads = 1);

  /// Whether the cell whose lowest corner is voxel `first` (by linear index) lies inside the
  /// image and has one label at its 16 corners.
  bool uniform(std::size_t first) const { return (bits_[first >> 6] >> (first & 63)) & 1; }

  std::size_t memory_bytes() const { return bits_.size() * sizeof(std::uint64_t); }

 private:
  std::vector<std::uint64_t> bits_;  // one per voxel: the cell it is the lowest corner of
};

}  // namespace mesh4d::domain
