// Work split into shares on the job's threads (the refiner's pinch counts, repair points and
// extraction between its parallel phases; the mesh statistics): part p of `parts` runs on its own
// thread, part 0 on the caller's, and the call returns when all are done. The first exception a
// part throws is rethrown here.
#pragma once

#include <algorithm>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace mesh4d::support {

template <class Fn>
void run_parts(unsigned parts, Fn&& fn) {
  if (parts <= 1) {
    fn(0u);
    return;
  }
  std::mutex error_mutex;
  std::exception_ptr error;
  const auto guarded = [&](unsigned p) {
    try {
      fn(p);
    } catch (...) {
      std::lock_guard lock(error_mutex);
      if (!error) error = std::current_exception();
    }
  };
  {
    std::vector<std::jthread> pool;
    pool.reserve(parts - 1);
    for (unsigned p = 1; p < parts; ++p) pool.emplace_back(guarded, p);
    guarded(0);
  }  // joins
  if (error) std::rethrow_exception(error);
}

// The half-open range [begin, end) of part p when n items are split into `parts`.
inline std::pair<std::size_t, std::size_t> part_range(std::size_t n, unsigned p, unsigned parts) {
  return {n * p / parts, n * (p + 1) / parts};
}

// How many parts `items` make on up to `threads` threads with at least `min_share` items each
// (a smaller share is not worth a thread); at least one.
inline unsigned parts_for(std::size_t items, std::size_t min_share, unsigned threads) {
  return static_cast<unsigned>(
      std::clamp<std::size_t>(items / min_share, 1, std::max(threads, 1u)));
}

}  // namespace mesh4d::support
