#include "refine/work_regions.h"

#include <algorithm>
#include <cmath>

namespace mesh4d::refine {

namespace {

// Bit i of each of the four coordinates (4 bits each) at bits 4i..4i+3: Morton order.
std::uint32_t interleave(const std::array<std::uint32_t, 4>& k) {
  std::uint32_t code = 0;
  for (int bit = 0; bit < 4; ++bit)
    for (int axis = 0; axis < 4; ++axis) code |= ((k[axis] >> bit) & 1u) << (4 * bit + axis);
  return code;
}

}  // namespace

WorkRegions::WorkRegions(const std::array<Point4, 2>& box, unsigned threads)
    : owner_(new std::atomic<std::uint16_t>[kBlocks]) {
  for (std::uint32_t b = 0; b < kBlocks; ++b) owner_[b].store(0, std::memory_order_relaxed);
  origin_ = box[0];
  // Cubes of the side that gives the box about kBlocksPerThread blocks a thread, each axis
  // rounded to a power of 2 (at least 1, at most 16).
  std::array<double, 4> extent{};
  double volume = 1;
  for (int a = 0; a < 4; ++a) {
    extent[a] = std::max(box[1][a] - box[0][a], 1e-9);
    volume *= extent[a];
  }
  const double wanted = double(std::max(threads, 1u)) * kBlocksPerThread;
  const double side = std::pow(volume / wanted, 0.25);
  for (int a = 0; a < 4; ++a) {
    const double n = std::clamp(extent[a] / side, 1.0, 16.0);
    count_[a] = 1 << std::clamp(int(std::lround(std::log2(n))), 0, 4);
    per_length_[a] = count_[a] / extent[a];
  }
}

std::uint32_t WorkRegions::block_of(const Point4& p) const {
  std::array<std::uint32_t, 4> k{};
  for (int a = 0; a < 4; ++a) {
    const double x = (p[a] - origin_[a]) * per_length_[a];
    // NaN and points outside the box go to the nearest block.
    k[a] = x >= 1 ? static_cast<std::uint32_t>(std::min(x, double(count_[a] - 1))) : 0;
  }
  return interleave(k);
}

}  // namespace mesh4d::refine
