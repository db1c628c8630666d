// A stack of plain values in fixed-size blocks: the refiner's per-rule queues.
//
// Why not std::vector: the sequential refiner's R1 stack holds most pentatopes ever made (on
// the hypersphere 0.4M of the 0.5M it queues, most of them dead by the time they are popped),
// and a doubling vector copied all of them at each growth, held the old and the new buffer at
// once and faulted in every new buffer's pages again: 1–3 % of the hypersphere's time
// (docs/performance.md, "Sequential refinement"). Blocks never move and are kept when the stack
// shrinks, so a push costs no copy and the pages are faulted in once, at the stack's peak. The
// blocks are a ChunkedArray's (the triangulation's own storage); this adds the count and the
// stack's moves.
#pragma once

#include <cstddef>
#include <vector>

#include "support/chunked_array.h"

namespace mesh4d::support {

template <class T>
class BlockStack {
 public:
  bool empty() const { return size_ == 0; }
  std::size_t size() const { return size_; }

  T& operator[](std::size_t i) { return items_[i]; }
  const T& operator[](std::size_t i) const { return items_[i]; }
  T& back() { return (*this)[size_ - 1]; }

  void push_back(const T& value) {
    items_.ensure(size_ + 1);
    items_[size_++] = value;
  }
  void pop_back() { --size_; }
  /// Keeps the blocks: the next pushes reuse their pages.
  void clear() { size_ = 0; }

  template <class Iterator>
  void append(Iterator first, Iterator last) {
    for (; first != last; ++first) push_back(*first);
  }
  template <class Iterator>
  void assign(Iterator first, Iterator last) {
    clear();
    append(first, last);
  }
  /// Appends every element, bottom first, to `out`.
  void copy_to(std::vector<T>& out) const {
    for (std::size_t i = 0; i < size_; ++i) out.push_back((*this)[i]);
  }
  /// Moves the bottom `count` elements (the oldest) to `out`, in order; the rest move down.
  void take_bottom(std::size_t count, std::vector<T>& out) {
    out.clear();
    for (std::size_t i = 0; i < count; ++i) out.push_back((*this)[i]);
    for (std::size_t i = count; i < size_; ++i) (*this)[i - count] = (*this)[i];
    size_ -= count;
  }

 private:
  // Blocks of 4096 elements: 96 KiB of candidates, small beside a queue's peak.
  ChunkedArray<T> items_{12};
  std::size_t size_ = 0;
};

}  // namespace mesh4d::support
