// How many of each region's boundary facets contain each triangle, kept up to date from the
// facets that appear and disappear, so that the pinch repair's rounds can count pinches
// without walking around every triangle that changed (pinch_repair.cpp, facet_log.cpp).
//
// A region-boundary facet separates two pentatopes of different output labels; it is a
// boundary facet of each side's region, except the background's (label 0). A triangle is
// pinched for a label when more than two of that label's boundary facets contain it (a
// 3-manifold boundary has exactly two).
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

namespace mesh4d::refine {

using PinchKey = std::array<std::uint32_t, 4>;  // label, then the triangle's sorted vertices

inline std::uint64_t hash_key(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t d) {
  std::uint64_t h = (std::uint64_t(a) << 32 | b) * 0x9E3779B97F4A7C15ull;
  h ^= (std::uint64_t(c) << 32 | d) * 0xC2B2AE3D27D4EB4Full;
  return h ^ (h >> 29);
}

class PinchCounts {
 public:
  /// Adds `delta` to the count of (label, triangle); label 0 is not counted. A key whose count
  /// falls to 0 is dropped: the table holds the boundary triangles of now, 16 bytes each.
  /// `cell`: a pentatope through the triangle, kept with a key whose count goes above two.
  void add(const PinchKey& key, int delta, std::uint32_t cell = 0) {
    if (key[0] == 0) return;
    if (2 * (used_ + 1) > table_.size()) grow();
    const std::size_t i = find(key);
    Slot& slot = table_[i];
    if (slot.label == 0) slot = {{key[1], key[2], key[3]}, std::uint16_t(key[0]), 0}, ++used_;
    const int before = slot.count;
    slot.count = static_cast<std::int16_t>(before + delta);
    if (before <= 2 && slot.count > 2) over_.push_back({key, cell});
    if (slot.count == 0) erase(i);
  }

  /// Room for `keys` keys without growing.
  void reserve(std::size_t keys) {
    std::size_t size = 64;
    while (size < 2 * keys + 2) size *= 2;
    if (size > table_.size()) rehash(size);
  }

  struct Pinch {
    PinchKey key;
    std::uint32_t cell;  // given when its count last went above two (it may have died since)
  };
  /// The keys whose count is now above two, sorted.
  std::vector<Pinch> pinched() {
    // The latest cell of a key that went above two more than once.
    std::stable_sort(over_.begin(), over_.end(),
                     [](const Pinch& a, const Pinch& b) { return a.key < b.key; });
    std::size_t kept = 0;
    for (std::size_t i = 0; i < over_.size(); ++i)
      if ((i + 1 == over_.size() || over_[i + 1].key != over_[i].key) && count(over_[i].key) > 2)
        over_[kept++] = over_[i];
    over_.resize(kept);
    return over_;
  }

  int count(const PinchKey& key) const {
    if (table_.empty()) return 0;
    const Slot& slot = table_[find(key)];
    return slot.label == 0 ? 0 : slot.count;
  }
  std::size_t size() const { return used_; }
  /// Whether both hold the same keys with the same counts.
  bool operator==(const PinchCounts& other) const {
    if (used_ != other.used_) return false;
    for (const Slot& s : table_)
      if (s.label != 0 &&
          other.count({s.label, s.triangle[0], s.triangle[1], s.triangle[2]}) != s.count)
        return false;
    return true;
  }

  void clear() {
    table_ = {};
    over_ = {};
    used_ = 0;
  }

 private:
  struct Slot {
    std::array<std::uint32_t, 3> triangle;
    std::uint16_t label;  // 0: empty
    std::int16_t count;   // (logs of parallel workers, applied one worker after the other, can
                          // take it below 0 for a while)
  };
  static_assert(sizeof(Slot) == 16);

  static std::size_t home(const Slot& s, std::size_t mask) {
    return hash_key(s.label, s.triangle[0], s.triangle[1], s.triangle[2]) & mask;
  }
  std::size_t find(const PinchKey& key) const {
    const std::size_t mask = table_.size() - 1;
    for (std::size_t i = hash_key(key[0], key[1], key[2], key[3]) & mask;; i = (i + 1) & mask) {
      const Slot& s = table_[i];
      if (s.label == 0 || (s.label == key[0] && s.triangle[0] == key[1] &&
                           s.triangle[1] == key[2] && s.triangle[2] == key[3]))
        return i;
    }
  }
  void erase(std::size_t i) {
    // Linear probing's deletion: later slots of the same run move back where their probe
    // sequence still reaches them.
    const std::size_t mask = table_.size() - 1;
    for (std::size_t j = (i + 1) & mask; table_[j].label != 0; j = (j + 1) & mask) {
      const std::size_t k = home(table_[j], mask);
      const bool stays = i <= j ? (i < k && k <= j) : (i < k || k <= j);
      if (stays) continue;
      table_[i] = table_[j];
      i = j;
    }
    table_[i].label = 0;
    --used_;
  }
  void grow() { rehash(std::max<std::size_t>(64, 2 * table_.size())); }
  void rehash(std::size_t size) {
    std::vector<Slot> old(size, Slot{{}, 0, 0});
    old.swap(table_);
    for (const Slot& s : old)
      if (s.label != 0) table_[find({s.label, s.triangle[0], s.triangle[1], s.triangle[2]})] = s;
  }

  std::vector<Slot> table_;  // open addressing, a power of two, at most half full
  std::size_t used_ = 0;
  std::vector<Pinch> over_;  // the keys whose count went above two (some since fell back)
};

}  // namespace mesh4d::refine
