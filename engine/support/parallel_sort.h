// std::sort on the job's threads: each thread sorts a share, then the shares are merged
// pairwise, the merges of one round side by side. The same order as std::sort for any thread
// count when the comparison is a strict total order (no two elements equal unless identical),
// as it is for the certificate's tuples. (std::execution::par would need TBB's headers, which
// the build does not install.)
#pragma once

#include <algorithm>
#include <cstddef>
#include <iterator>
#include <vector>

#include "support/parallel_parts.h"

namespace mesh4d::support {

// Fewer elements than this a share are sorted on one thread.
inline constexpr std::size_t kMinSortShare = std::size_t{1} << 15;

template <class T, class Less = std::less<>>
void parallel_sort(std::vector<T>& v, unsigned threads, Less less = {}) {
  const std::size_t n = v.size();
  unsigned parts = 1;
  while (parts * 2 <= threads && n / (parts * 2) >= kMinSortShare) parts *= 2;
  if (parts == 1) {
    std::sort(v.begin(), v.end(), less);
    return;
  }
  const auto at = [&](unsigned p) {
    return v.begin() + static_cast<std::ptrdiff_t>(part_range(n, p, parts).first);
  };
  run_parts(parts,
            [&](unsigned p) { std::sort(at(p), p + 1 < parts ? at(p + 1) : v.end(), less); });
  // Rounds of pairwise merges: shares of width 1, 2, 4, ... parts become one.
  for (unsigned width = 1; width < parts; width *= 2) {
    const unsigned merges = parts / (2 * width);
    run_parts(merges, [&](unsigned m) {
      const unsigned first = 2 * width * m;
      const auto end = first + 2 * width < parts ? at(first + 2 * width) : v.end();
      std::inplace_merge(at(first), at(first + width), end, less);
    });
  }
}

}  // namespace mesh4d::support
