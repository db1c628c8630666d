// The vertex locks of one thread of the parallel refiner: a try-lock per vertex (its lock word
// in the store holds the owning thread's id), and the list of what this thread holds, released
// together when its operation commits or rolls back.
#pragma once

#include <atomic>
#include <cstdint>
#include <vector>

#include "delaunay/cell_guard.h"

namespace mesh4d::delaunay {

class VertexLocks final : public CellGuard {
 public:
  /// `owner` identifies the thread: any value but 0 (the unlocked word), distinct per thread.
  VertexLocks(PentatopeStore& store, std::uint32_t owner) : store_(store), owner_(owner) {}
  VertexLocks(const VertexLocks&) = delete;
  VertexLocks& operator=(const VertexLocks&) = delete;

  std::uint32_t owner() const { return owner_; }

  /// Locks v unless another thread holds it; true when this thread holds it now.
  bool lock(VertexId v) {
    std::atomic_ref word(store_.owner(v));
    std::uint32_t current = word.load(std::memory_order_relaxed);
    if (current == owner_) return true;
    if (current != 0) return false;
    if (!word.compare_exchange_strong(current, owner_, std::memory_order_acquire,
                                      std::memory_order_relaxed))
      return false;
    held_.push_back(v);
    return true;
  }
  /// Takes a vertex this thread created already locked (PentatopeStore::add_vertex's owner).
  void adopt(VertexId v) { held_.push_back(v); }

  bool acquire(CellId c) override {
    const Pentatope& cell = store_.cell(c);
    for (VertexId v : cell.v)
      if (!lock(v)) return false;
    return true;
  }

  void release_all() {
    for (VertexId v : held_) std::atomic_ref(store_.owner(v)).store(0, std::memory_order_release);
    held_.clear();
  }
  std::size_t held() const { return held_.size(); }

 private:
  PentatopeStore& store_;
  std::uint32_t owner_;
  std::vector<VertexId> held_;
};

}  // namespace mesh4d::delaunay
