// parallel_bench: the parallel refiner's scaling on the beating ventricle at the paper's size
// (100×100×44×15, δ = 5, R3 first), against one thread (the sequential path) measured in the
// same run. Per thread count, the median of --repeat runs (each a forked child): pentatopes,
// time, pentatopes/s, speedup, rollbacks, contention and idle thread-seconds, and the share of
// the time spent in the rules (the parallel part; pinch repair and relabeling between rule
// phases run on one thread), with the output's quality as a check.
//
//   parallel_bench [--threads 1,2,4,8] [--repeat 3] [--delta 5]
#include <algorithm>
#include <array>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "delaunay/checker.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"
#include "refine/refiner.h"

using namespace mesh4d;

namespace {

struct Run {
  std::uint64_t pentatopes, rollbacks, insertions[5], removals;
  double seconds, rules_seconds, contention, idle, rho_max, tau_min;
  bool valid;
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<unsigned> threads = {1, 2, 4, 8};
  int repeat = 3;
  double delta = 5;
  std::uint64_t seed = refine::RefineParams{}.seed;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--threads") == 0) {
      threads.clear();
      std::stringstream list(argv[i + 1]);
      for (std::string item; std::getline(list, item, ',');)
        threads.push_back(static_cast<unsigned>(std::stoul(item)));
    } else if (std::strcmp(argv[i], "--repeat") == 0) {
      repeat = std::max(1, std::atoi(argv[i + 1]));
    } else if (std::strcmp(argv[i], "--delta") == 0) {
      delta = std::atof(argv[i + 1]);
    } else if (std::strcmp(argv[i], "--seed") == 0) {
      seed = std::strtoull(argv[i + 1], nullptr, 10);
    }
  }
  auto image = domain::beating_ventricle_phantom();
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);

  std::printf(
      "Parallel refinement, beating ventricle 100x100x44x15, δ = %g, R3 first; median of %d runs "
      "(seeds %llu..%llu); "
      "speedup against 1 thread in this run\n",
      delta, repeat, static_cast<unsigned long long>(seed),
      static_cast<unsigned long long>(seed + static_cast<std::uint64_t>(repeat) - 1));
  std::printf(
      "| threads | pentatopes | time s | pentatopes/s | speedup | rules s | rollbacks | "
      "contention s | idle s | insertions R1 / R2 / R3 / R4 / R5 | R5 removals | max ρ | min τ | "
      "valid |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  double reference = 0;
  for (unsigned t : threads) {
    std::vector<double> seconds, rules, contention, idle, pentatopes, rollbacks, rho, tau, removals;
    std::array<std::vector<double>, 5> insertions;
    bool valid = true;
    for (int k = 0; k < repeat; ++k) {
      const auto run = bench::run_in_child<Run>([&] {
        refine::RefineParams params;
        params.delta = delta;
        params.threads = t;
        // One seed per repeat: a parallel mesh depends on timing, so only an average over seeds
        // compares it fairly with the sequential one (whose mesh a single seed fixes).
        params.seed = seed + static_cast<std::uint64_t>(k);
        refine::Refiner refiner(oracle, params);
        const auto r = refiner.run();
        return Run{r.stats.pentatopes,
                   r.rollbacks,
                   {r.stats.insertions[0], r.stats.insertions[1], r.stats.insertions[2],
                    r.stats.insertions[3], r.stats.insertions[4]},
                   r.stats.removals[4],
                   r.stats.elapsed_seconds,
                   r.rules_seconds,
                   r.contention_seconds,
                   r.idle_seconds,
                   r.stats.radius_edge_ratio.max,
                   r.stats.normalized_volume.min,
                   delaunay::check_triangulation(refiner.triangulation()).ok};
      });
      if (!run) {
        valid = false;
        continue;
      }
      seconds.push_back(run->seconds);
      rules.push_back(run->rules_seconds);
      contention.push_back(run->contention);
      idle.push_back(run->idle);
      pentatopes.push_back(double(run->pentatopes));
      rollbacks.push_back(double(run->rollbacks));
      for (int r = 0; r < 5; ++r) insertions[r].push_back(double(run->insertions[r]));
      removals.push_back(double(run->removals));
      rho.push_back(run->rho_max);
      tau.push_back(run->tau_min);
      valid &= run->valid;
    }
    if (seconds.empty()) {
      std::printf("| %u | run failed |\n", t);
      continue;
    }
    const double time = median(seconds);
    if (reference == 0) reference = time;
    std::printf(
        "| %u | %.0f | %.2f | %.0f | %.2f | %.2f | %.0f | %.2f | %.2f | %.0f / %.0f / %.0f / %.0f "
        "/ "
        "%.0f | %.0f | %.2f | %.4f | %s |\n",
        t, median(pentatopes), time, median(pentatopes) / time, reference / time, median(rules),
        median(rollbacks), median(contention), median(idle), median(insertions[0]),
        median(insertions[1]), median(insertions[2]), median(insertions[3]), median(insertions[4]),
        median(removals), *std::max_element(rho.begin(), rho.end()),
        *std::min_element(tau.begin(), tau.end()), valid ? "yes" : "NO");
    std::fflush(stdout);
  }
}
