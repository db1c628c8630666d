// A growable array of trivially copyable values stored in fixed-size blocks.
//
// Why not std::vector: a vector that doubles copies every element and, for a moment, holds the
// old and the new buffer (up to 3× the data at peak); a triangulation of 10⁶ points has 3·10⁷
// pentatopes, and that peak would break the memory budget. Blocks never move, so growth costs
// no copy and elements keep their address. Blocks are allocated uninitialised: pages are
// committed by the kernel only when first written.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

namespace mesh4d::delaunay {

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

  std::size_t size() const { return size_; }

  /// Appends a value and returns its index.
  std::size_t push_back(const T& value) {
    if (size_ == blocks_.size() << shift_)
      blocks_.push_back(std::make_unique_for_overwrite<T[]>(std::size_t{1} << shift_));
    (*this)[size_] = value;
    return size_++;
  }

  /// Bytes reserved by the blocks (not counting untouched pages the kernel never committed).
  std::size_t capacity_bytes() const { return (blocks_.size() << shift_) * sizeof(T); }

  void clear() {
    blocks_.clear();
    size_ = 0;
  }
  /// Empties the array but keeps its blocks for reuse.
  void reset() { size_ = 0; }

 private:
  unsigned shift_;
  std::size_t mask_;
  std::size_t size_ = 0;
  std::vector<std::unique_ptr<T[]>> blocks_;
};

}  // namespace mesh4d::delaunay
