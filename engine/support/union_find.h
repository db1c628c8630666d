// Disjoint sets over 0..n-1 with path halving: the pieces of a region, a link or an image label.
#pragma once

#include <cstddef>
#include <numeric>
#include <vector>

namespace mesh4d::support {

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  std::size_t find(std::size_t i) {
    while (parent_[i] != i) i = parent_[i] = parent_[parent_[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { parent_[find(a)] = find(b); }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace mesh4d::support
