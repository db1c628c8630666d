// Points on ∂Ω already in the mesh, in a hash grid of cell size Δ, answering R1's question: is
// there a feature vertex within Δ of z?
//
// Asked twice for most pentatopes the rules classify (half a million times on the ventricle),
// so the grid is flat: an open-addressing table from cell to the newest point in it, and each
// point linked to the previous one of its cell. (A std::unordered_map of vectors spent most of
// its time in the modulo of its bucket index and in chasing its nodes.)
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::refine {

class FeatureIndex {
 public:
  explicit FeatureIndex(double cell) : cell_(cell), inverse_(1 / cell), table_(kInitialSlots) {}

  void add(const Point4& p) {
    if (2 * (used_ + 1) > table_.size()) grow();
    Slot& slot = find(key(cell_of(p)));
    if (slot.head == kEmpty) ++used_;
    next_.push_back(slot.head);
    slot.head = static_cast<std::uint32_t>(points_.size());
    points_.push_back(p);
  }

  std::size_t size() const { return points_.size(); }

  /// A partial any_within(): only the points in p's own grid cell are measured. True means
  /// some point lies within r of p; false may miss one (for shortcuts that only save work).
  bool any_within_own_cell(const Point4& p, double r) const {
    return any_within_own_cell_such(p, r, [](const Point4&) { return true; });
  }

  /// Whether some added point q in p's own grid cell lies strictly within distance r of p and
  /// also passes accept(q). False may miss one elsewhere (for shortcuts that only save work).
  template <class Accept>
  bool any_within_own_cell_such(const Point4& p, double r, Accept accept) const {
    return any_in_cell(cell_of(p), p, r * r, accept);
  }

  /// Whether some added point lies strictly within distance r (≤ the cell size) of p.
  bool any_within(const Point4& p, double r) const {
    // Only the grid cells that the box around the ball overlaps: 1 to 16 of them (of the 81
    // around p), fewer the smaller r. Most questions are answered yes, mostly by a point in
    // p's own cell, so that one is read first.
    const std::array<std::int64_t, 4> own = cell_of(p);
    if (any_in_cell(own, p, r * r)) return true;
    std::array<std::int64_t, 4> lo, hi;
    for (int a = 0; a < 4; ++a) {
      lo[a] = cell_index(p[a] - r);
      hi[a] = cell_index(p[a] + r);
    }
    std::array<std::int64_t, 4> n;
    for (n[3] = lo[3]; n[3] <= hi[3]; ++n[3])
      for (n[2] = lo[2]; n[2] <= hi[2]; ++n[2])
        for (n[1] = lo[1]; n[1] <= hi[1]; ++n[1])
          for (n[0] = lo[0]; n[0] <= hi[0]; ++n[0])
            if (n != own && any_in_cell(n, p, r * r)) return true;
    return false;
  }

 private:
  static constexpr std::uint32_t kEmpty = 0xFFFFFFFFu;
  static constexpr std::size_t kInitialSlots = 1024;  // a power of two
  struct Slot {
    std::uint64_t key = 0;
    std::uint32_t head = kEmpty;  // newest point of the cell
  };

  // Whether a point of `cell` lies strictly within sqrt(r2) of p and passes accept().
  template <class Accept = bool (*)(const Point4&)>
  bool any_in_cell(
      const std::array<std::int64_t, 4>& cell, const Point4& p, double r2,
      Accept accept = [](const Point4&) { return true; }) const {
    for (std::uint32_t i = find(key(cell)).head; i != kEmpty; i = next_[i])
      if (squared_distance(p, points_[i]) < r2 && accept(points_[i])) return true;
    return false;
  }
  std::int64_t cell_index(double x) const {
    return static_cast<std::int64_t>(std::floor(x * inverse_));
  }
  std::array<std::int64_t, 4> cell_of(const Point4& p) const {
    return {cell_index(p[0]), cell_index(p[1]), cell_index(p[2]), cell_index(p[3])};
  }
  // 16 bits per axis: distinct for cells within 2^15 cells of the origin along every axis.
  // Farther cells may share a key; their points then share a list, which is still correct
  // (every point is measured), only slower.
  static std::uint64_t key(const std::array<std::int64_t, 4>& c) {
    std::uint64_t k = 0;
    for (std::int64_t v : c) k = k << 16 | (static_cast<std::uint64_t>(v + (1 << 15)) & 0xFFFF);
    return k;
  }
  static std::uint64_t hash(std::uint64_t k) {
    k *= 0x9E3779B97F4A7C15ull;
    return k ^ (k >> 32);
  }
  // The slot of key k, or the empty slot where it would go.
  Slot& find(std::uint64_t k) {
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = hash(k) & mask;; i = (i + 1) & mask)
      if (table_[i].head == kEmpty || table_[i].key == k) {
        table_[i].key = k;  // harmless on a miss: a slot is empty exactly while head is
        return table_[i];
      }
  }
  const Slot& find(std::uint64_t k) const {
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = hash(k) & mask;; i = (i + 1) & mask)
      if (table_[i].head == kEmpty || table_[i].key == k) return table_[i];
  }
  void grow() {
    std::vector<Slot> old(2 * table_.size());
    old.swap(table_);
    for (const Slot& s : old)
      if (s.head != kEmpty) find(s.key).head = s.head;
  }

  double cell_;
  double inverse_;
  std::vector<Slot> table_;
  std::size_t used_ = 0;             // occupied slots
  std::vector<Point4> points_;       // in insertion order
  std::vector<std::uint32_t> next_;  // the previous point of the same cell, or kEmpty
};

}  // namespace mesh4d::refine
