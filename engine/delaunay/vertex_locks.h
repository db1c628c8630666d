// The vertex locks of one thread of the parallel refiner: a try-lock per vertex (its lock word
// in the store holds the owning thread's id), and the list of what this thread holds, released
// together when its operation commits or rolls back.
#pragma once

#include <atomic>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {

class VertexLocks final {
 public:
  /// A lock that another thread held: the vertex and that thread's id.
  struct Blocker {
    VertexId vertex;
    std::uint32_t owner;
  };

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
    if (current == 0 && word.compare_exchange_strong(current, owner_, std::memory_order_acquire,
                                                     std::memory_order_relaxed)) {
      held_.push_back(v);
      return true;
    }
    blocker_ = Blocker{v, current};
    return false;
  }
  /// Takes a vertex this thread created already locked (PentatopeStore::add_vertex's owner).
  void adopt(VertexId v) { held_.push_back(v); }

  /// Claims pentatope c (whose vertex ids the caller may read: it holds four of them already).
  /// False when another thread holds one of its vertices.
  bool acquire(CellId c) {
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

  /// The last lock that failed since the last call, if one did.
  std::optional<Blocker> take_blocker() { return std::exchange(blocker_, std::nullopt); }
  /// Whether the blocker still holds its vertex.
  bool still_held(const Blocker& b) const {
    return std::atomic_ref(store_.owner(b.vertex)).load(std::memory_order_acquire) == b.owner;
  }

 private:
  PentatopeStore& store_;
  std::uint32_t owner_;
  std::vector<VertexId> held_;
  std::optional<Blocker> blocker_;
};

}  // namespace mesh4d::delaunay
