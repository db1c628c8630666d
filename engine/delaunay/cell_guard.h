// How a concurrent operation on the shared triangulation claims the pentatopes it touches.
//
// The rule every thread follows (the parallel refiner's locking, docs/algorithm.md, "Parallel
// refinement"): it reads or writes a pentatope only while it holds at least four of the
// pentatope's vertices, and reads the pentatope's neighbors only while it holds all five. Two
// threads can never both hold four vertices of one pentatope, so no pentatope is ever read
// while another thread writes it. The triangulation asks the guard before it steps into a
// pentatope (a walk, a cavity search, a star); the guard locks its vertices or refuses, and a
// refusal abandons the operation before anything was written.
#pragma once

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {

class CellGuard {
 public:
  /// Claims pentatope c (whose vertex ids the caller may read: it holds four of them already).
  /// False when another thread holds one of its vertices.
  virtual bool acquire(CellId c) = 0;

 protected:
  ~CellGuard() = default;
};

}  // namespace mesh4d::delaunay
