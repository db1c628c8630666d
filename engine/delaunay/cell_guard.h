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

#include "delaunay/vertex_locks.h"

namespace mesh4d::delaunay {

// The one way to claim (a concrete type, so that the walks and cavity searches call its
// acquire() inline).
using CellGuard = VertexLocks;

}  // namespace mesh4d::delaunay
