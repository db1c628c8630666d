// Stage 1 of in-sphere (the semi-static filter) for four pentatopes against one point at once:
// cavity search tests the neighbors of each cavity pentatope, and their tests share the point.
//
// Each lane evaluates exactly insphere_semi_static() of predicate_kernels.h: the same expression
// tree, the same bound, no fused multiply-adds, so the same answer bit for bit (a test compares
// them). Where the processor has AVX2 the four lanes share each instruction; elsewhere two.
#pragma once

#include "delaunay/point4.h"

namespace mesh4d::delaunay::detail {

/// vertices[l]: the five vertices of pentatope l (finite). out[l]: 1 (q inside its
/// circumsphere), -1 (outside) or kUndecided. With `portable`, the code for processors without
/// AVX2 even where it has it (tests compare both).
void insphere_semi_static4(const Point4* const vertices[4][5], const Point4& q, int out[4],
                           bool portable = false);

}  // namespace mesh4d::delaunay::detail
