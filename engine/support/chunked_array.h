// A growable array of trivially copyable values stored in fixed-size blocks.
//
// Why not std::vector: a vector that doubles copies every element and, for a moment, holds the
// old and the new buffer (up to 3× the data at peak); a triangulation of 10⁶ points has 3·10⁷
// pentatopes, and that peak would break the memory budget. Blocks never move, so growth costs
// no copy and elements keep their address. Blocks are allocated uninitialised: pages are
// committed by the kernel only when first written.
//
// The array does not count its elements: its owner hands out indices and calls ensure() before
// using one. Concurrent use (the parallel refiner): after reserve_blocks(), the table of block
// pointers never moves, so ensure() may add blocks (it takes a mutex) while other threads read
// and write elements of the blocks that exist.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <type_traits>
#include <vector>

namespace mesh4d::support {

template <class T>
class ChunkedArray {
  static_assert(std::is_trivially_copyable_v<T>, "ChunkedArray holds plain data only");

 public:
  /// Blocks hold 2^block_shift elements: large for a whole mesh, small for the little
  /// triangulations built during vertex removal.
  explicit ChunkedArray(unsigned block_shift = 16)
      : shift_(block_shift), mask_((std::size_t{1} << block_shift) - 1) {}

  T& operator[](std::size_t i) { return blocks_[i >> shift_][i & mask_]; }
  const T& operator[](std::size_t i) const { return blocks_[i >> shift_][i & mask_]; }

  /// Makes room for up to `elements` without ever moving the block table: required before
  /// concurrent ensure().
  void reserve_blocks(std::size_t elements) {
    std::lock_guard lock(grow_);
    blocks_.reserve((elements >> shift_) + 1);
    reserved_ = blocks_.capacity() << shift_;
  }

  /// Allocates the blocks that indices below n need. Safe alongside readers of existing blocks
  /// once reserve_blocks() covered n; throws std::length_error past the reservation then.
  void ensure(std::size_t n) {
    if (n <= capacity_.load(std::memory_order_acquire)) return;
    std::lock_guard lock(grow_);
    if (reserved_ != 0 && n > reserved_)
      throw std::length_error("ChunkedArray: more elements than reserved for concurrent growth");
    while ((blocks_.size() << shift_) < n)
      blocks_.push_back(std::make_unique_for_overwrite<T[]>(std::size_t{1} << shift_));
    capacity_.store(blocks_.size() << shift_, std::memory_order_release);
  }

  /// Bytes reserved by the blocks (not counting untouched pages the kernel never committed).
  std::size_t capacity_bytes() const { return (blocks_.size() << shift_) * sizeof(T); }

 private:
  unsigned shift_;
  std::size_t mask_;
  std::vector<std::unique_ptr<T[]>> blocks_;
  // For ensure(): the elements the allocated blocks hold, and the limit of reserve_blocks().
  std::atomic<std::size_t> capacity_{0};
  std::size_t reserved_ = 0;
  std::mutex grow_;
};

}  // namespace mesh4d::support
