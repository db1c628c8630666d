// Spatially coherent insertion order for point batches (CGAL's spatial_sort: a Hilbert curve
// order over a biased randomized insertion order, BRIO), so that each point is located from the
// previous one in a few walk steps.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

#include "delaunay/point4.h"

namespace mesh4d::delaunay {

/// A permutation of 0..points.size()-1 in spatial-sort order. Deterministic for given input.
std::vector<std::size_t> spatial_order(std::span<const Point4> points);

}  // namespace mesh4d::delaunay
