// Disjoint sets over 0..n-1 that several threads may join at once. A set's root is always its
// smallest element (a root is only ever linked under a smaller one), so the sets and their roots
// come out the same whatever order the threads join in: callers that break ties by root get
// the same answer with any number of threads.
#pragma once

#include <atomic>
#include <cstddef>
#include <numeric>
#include <utility>
#include <vector>

namespace mesh4d::support {

class ConcurrentUnionFind {
 public:
  explicit ConcurrentUnionFind(std::size_t n) : parent_(n) {
    std::iota(parent_.begin(), parent_.end(), 0);
  }

  /// The root of i's set; safe while other threads join.
  std::size_t find(std::size_t i) {
    while (true) {
      const std::size_t p = load(i);
      if (p == i) return i;
      const std::size_t g = load(p);
      // Path halving: i to its grandparent, an ancestor whatever happened since (a failed
      // exchange only means another thread shortened the path first).
      if (g != p) {
        std::size_t expected = p;
        std::atomic_ref(parent_[i])
            .compare_exchange_weak(expected, g, std::memory_order_acq_rel,
                                   std::memory_order_relaxed);
      }
      i = g;
    }
  }

  void join(std::size_t a, std::size_t b) {
    while (true) {
      a = find(a);
      b = find(b);
      if (a == b) return;
      if (a < b) std::swap(a, b);
      // a, the larger root, goes under b, unless another thread linked a meanwhile.
      std::size_t expected = a;
      if (std::atomic_ref(parent_[a])
              .compare_exchange_strong(expected, b, std::memory_order_acq_rel,
                                       std::memory_order_acquire))
        return;
    }
  }

 private:
  std::size_t load(std::size_t i) {
    return std::atomic_ref(parent_[i]).load(std::memory_order_acquire);
  }
  std::vector<std::size_t> parent_;
};

}  // namespace mesh4d::support
