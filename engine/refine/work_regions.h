// The blocks of space that the workers of a parallel phase own (docs/refinement.md, "Parallel
// refinement"): a grid over the refinement box, at most 16 blocks an axis, shaped like the box,
// about kBlocksPerThread blocks for each worker. Blocks are numbered in Morton order, so a range
// of numbers is a compact piece of space. A new candidate goes to the worker that owns the
// block its circumcenter lies in; a worker that runs dry takes over the blocks of the work it
// steals. Ownership only keeps the workers apart: the vertex locks still make every operation
// safe, so an owner read while it changes does no harm.
#pragma once

#include <array>
#include <atomic>
#include <cstdint>
#include <memory>

#include "delaunay/point4.h"

namespace mesh4d::refine {

class WorkRegions {
 public:
  static constexpr unsigned kBlocksPerThread = 32;
  static constexpr std::uint32_t kBlocks = 1u << 16;  // block numbers: 4 bits an axis

  WorkRegions(const std::array<Point4, 2>& box, unsigned threads);

  /// The block that holds p (a point outside the box: the nearest block).
  std::uint32_t block_of(const Point4& p) const;
  unsigned owner(std::uint32_t block) const {
    return owner_[block].load(std::memory_order_relaxed);
  }
  void set_owner(std::uint32_t block, unsigned worker) {
    owner_[block].store(static_cast<std::uint16_t>(worker), std::memory_order_relaxed);
  }

 private:
  Point4 origin_{};
  std::array<double, 4> per_length_{};  // blocks per unit of length, by axis
  std::array<int, 4> count_{};          // blocks along each axis (a power of 2, at most 16)
  std::unique_ptr<std::atomic<std::uint16_t>[]> owner_;
};

}  // namespace mesh4d::refine
