// Pairs the new pentatopes of a Bowyer–Watson star across their shared facets. Keys are ridges
// (triangles, three vertex ids); each ridge is offered exactly twice, and the second offer gets
// the first one's pentatope and slot back. Open addressing in a table that is reused from one
// insertion to the next: a generation number marks the live entries, so nothing is cleared.
#pragma once

#include <algorithm>
#include <cstdint>
#include <vector>

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {

class RidgeTable {
 public:
  struct Match {
    CellId cell = kNoCell;  // the pentatope that offered the same ridge first, or kNoCell
    int slot = -1;          // its slot opposite the ridge's facet
  };

  /// Starts a new round for up to `ridges` distinct ridges.
  void begin(std::size_t ridges) {
    std::size_t size = 64;
    while (size < 2 * ridges) size *= 2;
    if (size > entries_.size()) {
      entries_.assign(size, Entry{});
      generation_ = 0;
    }
    mask_ = entries_.size() - 1;
    if (++generation_ == 0) {  // wrapped: clear once
      std::fill(entries_.begin(), entries_.end(), Entry{});
      generation_ = 1;
    }
  }

  /// Offers ridge r (any order) of pentatope `cell`, whose facet holding it is opposite `slot`.
  Match pair(VertexId r[3], CellId cell, int slot) {
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    if (r[1] > r[2]) std::swap(r[1], r[2]);
    if (r[0] > r[1]) std::swap(r[0], r[1]);
    std::size_t h = (r[0] * 0x9E3779B1u ^ r[1] * 0x85EBCA77u ^ r[2] * 0xC2B2AE3Du) & mask_;
    while (true) {
      Entry& e = entries_[h];
      if (e.generation != generation_) {
        e = Entry{{r[0], r[1], r[2]}, cell, slot, generation_};
        return {};
      }
      if (e.key[0] == r[0] && e.key[1] == r[1] && e.key[2] == r[2]) return {e.cell, e.slot};
      h = (h + 1) & mask_;
    }
  }

 private:
  struct Entry {
    VertexId key[3] = {0, 0, 0};
    CellId cell = kNoCell;
    int slot = -1;
    std::uint32_t generation = 0;
  };
  std::vector<Entry> entries_;
  std::size_t mask_ = 0;
  std::uint32_t generation_ = 0;
};

}  // namespace mesh4d::delaunay
