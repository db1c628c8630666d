// A pentatope's facet as its four vertex ids in increasing order: the key under which the two
// pentatopes that share it meet (hole filling, the pinch counts).
#pragma once

#include <algorithm>
#include <array>

#include "delaunay/pentatope_store.h"

namespace mesh4d::delaunay {

using FacetKey = std::array<VertexId, 4>;

/// The facet of a pentatope with vertices v opposite v[opposite], sorted.
inline FacetKey facet_key(const VertexId v[5], int opposite) {
  FacetKey key;
  for (int i = 0, k = 0; i < 5; ++i)
    if (i != opposite) key[k++] = v[i];
  // A sorting network: five compare-exchanges, no calls (std::sort was a tenth of a removal).
  const auto order = [&](int i, int j) {
    const VertexId lo = std::min(key[i], key[j]), hi = std::max(key[i], key[j]);
    key[i] = lo, key[j] = hi;
  };
  order(0, 1), order(2, 3), order(0, 2), order(1, 3), order(1, 2);
  return key;
}

}  // namespace mesh4d::delaunay
