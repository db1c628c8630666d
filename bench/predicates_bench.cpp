// predicates_bench: calls per second of mesh4d's orient4 / insphere4 against CGAL's Epick_d
// functors (the reference, timed in the same run on the same inputs), on random points and on
// an exact grid (where ties force the exact path). Prints medians of 5 repetitions and the
// exact-fallback rate.
#include <CGAL/Epick_d.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <random>
#include <vector>

#include "delaunay/predicates.h"

using mesh4d::Point4;
using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<4>>;
using CgalPoint = Kernel::Point_d;

namespace {

constexpr int kTuples = 200'000;
constexpr int kRepeats = 5;

std::vector<Point4> make_points(bool grid, std::mt19937_64& rng) {
  std::vector<Point4> pts(kTuples * 6);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::uniform_int_distribution<int> g(0, 3);
  for (auto& p : pts)
    for (double& c : p) c = grid ? g(rng) : u(rng);
  return pts;
}

template <class F>
double median_rate(F&& run) {
  std::vector<double> rates;
  for (int r = 0; r < kRepeats; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    run();
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    rates.push_back(kTuples / s);
  }
  std::sort(rates.begin(), rates.end());
  return rates[kRepeats / 2];
}

volatile long g_sink;  // keeps results alive

void bench(const char* name, const std::vector<Point4>& pts) {
  std::vector<CgalPoint> cp;
  for (const auto& p : pts) cp.emplace_back(p[0], p[1], p[2], p[3]);
  const Kernel kernel;
  auto cgal_orient = kernel.orientation_d_object();
  auto cgal_side = kernel.side_of_oriented_sphere_d_object();

  auto& counters = mesh4d::delaunay::predicate_counters();
  counters = {};
  const double ours_o = median_rate([&] {
    long s = 0;
    for (int i = 0; i < kTuples; ++i) {
      const Point4* p = &pts[6 * i];
      s += mesh4d::delaunay::orient4(p[0], p[1], p[2], p[3], p[4]);
    }
    g_sink = s;
  });
  const double ours_s = median_rate([&] {
    long s = 0;
    for (int i = 0; i < kTuples; ++i) {
      const Point4* p = &pts[6 * i];
      const Point4* simplex[5] = {&p[0], &p[1], &p[2], &p[3], &p[4]};
      s += mesh4d::delaunay::insphere4(simplex, p[5]);
    }
    g_sink = s;
  });
  const double cgal_o = median_rate([&] {
    long s = 0;
    for (int i = 0; i < kTuples; ++i) s += cgal_orient(cp.begin() + 6 * i, cp.begin() + 6 * i + 5);
    g_sink = s;
  });
  const double cgal_s = median_rate([&] {
    long s = 0;
    for (int i = 0; i < kTuples; ++i)
      s += cgal_side(cp.begin() + 6 * i, cp.begin() + 6 * i + 5, cp[6 * i + 5]);
    g_sink = s;
  });
  const double calls_o = double(counters.orient_calls), calls_s = double(counters.insphere_calls);
  std::printf("%-8s | orient4   | %10.2f | %10.2f | %5.2fx | %6.3f%%\n", name, ours_o / 1e6,
              cgal_o / 1e6, ours_o / cgal_o, 100.0 * counters.orient_exact / calls_o);
  std::printf("%-8s | insphere4 | %10.2f | %10.2f | %5.2fx | %6.3f%%\n", name, ours_s / 1e6,
              cgal_s / 1e6, ours_s / cgal_s, 100.0 * counters.insphere_exact / calls_s);
}

}  // namespace

int main() {
  std::mt19937_64 rng(2026);
  std::printf("%d point tuples, median of %d runs, M calls/s\n", kTuples, kRepeats);
  std::printf("input    | predicate | mesh4d     | CGAL Epick_d | ratio | exact fallback\n");
  bench("random", make_points(false, rng));
  bench("grid4^4", make_points(true, rng));
  return 0;
}
