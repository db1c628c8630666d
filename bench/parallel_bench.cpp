// parallel_bench: the parallel refiner's scaling on the beating ventricle at the paper's size
// (100×100×44×15, δ = 5, R3 first), against one thread (the sequential path) measured in the
// same run. Per thread count, the median of --repeat runs (each a forked child, one seed per
// repeat, the thread counts interleaved): pentatopes, time, pentatopes/s, speedup (of the
// median times) and paired speedup (over seeds, the median of a seed's time in the first row
// over its time in this one), rollbacks, contention and idle thread-seconds (and the workers'
// time split: work, rolled-back work, waiting, idle), the time spent in the rules (the parallel
// phases) and in each stage (the table says which run on one thread), with the output's quality
// as a check.
//
// With --ceiling on, the machine's own limit too: for each thread count N above 1, N one-thread
// runs of the same seed at once, as N independent processes (no shared mesh, no locks). Their
// throughput against one run alone is the most that N workers could give on this machine with
// this memory traffic; the code's speedup is set against it.
//
//   parallel_bench [--threads 1,2,4,8] [--repeat 3] [--delta 5] [--seed 1] [--ceiling on]
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
  std::uint64_t pentatopes, rollbacks, insertions[5], removals, fingerprint;
  double seconds, rules_seconds, contention, idle, rho_max, tau_min;
  bool valid;
  std::array<double, refine::kStages> stages;
  double work, rolled_back;
  double sag_offset, frame_fit, fit_rounds;  // of the extraction stage (refine/facet_sag.h)
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
  bool ceiling = false;
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
    } else if (std::strcmp(argv[i], "--ceiling") == 0) {
      ceiling = std::strcmp(argv[i + 1], "on") == 0;
    }
  }
  auto image = domain::beating_ventricle_phantom();
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);

  std::printf(
      "Parallel refinement, beating ventricle 100x100x44x15, δ = %g, R3 first; median of %d runs "
      "(seeds %llu..%llu); "
      "thread counts interleaved per seed; speedup against the first row in this run\n",
      delta, repeat, static_cast<unsigned long long>(seed),
      static_cast<unsigned long long>(seed + static_cast<std::uint64_t>(repeat) - 1));
  std::printf(
      "| threads | pentatopes | time s | pentatopes/s | speedup | paired speedup | rules s | "
      "rollbacks | contention s | idle s | insertions R1 / R2 / R3 / R4 / R5 | R5 removals | max ρ "
      "| min τ | valid |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const auto refine_once = [&](unsigned t, std::uint64_t run_seed) {
    refine::RefineParams params;
    params.delta = delta;
    params.threads = t;
    // One seed per repeat: a parallel mesh depends on timing, so only an average over seeds
    // compares it fairly with the sequential one (whose mesh a single seed fixes).
    params.seed = run_seed;
    refine::Refiner refiner(oracle, params);
    const auto r = refiner.run();
    return Run{r.stats.pentatopes,
               r.rollbacks,
               {r.stats.insertions[0], r.stats.insertions[1], r.stats.insertions[2],
                r.stats.insertions[3], r.stats.insertions[4]},
               r.stats.removals[4],
               bench::mesh_fingerprint(r.mesh),
               r.stats.elapsed_seconds,
               r.rules_seconds,
               r.contention_seconds,
               r.idle_seconds,
               r.stats.radius_edge_ratio.max,
               r.stats.normalized_volume.min,
               delaunay::check_triangulation(refiner.triangulation()).ok,
               r.stages.seconds,
               r.work_seconds,
               r.rolled_back_seconds,
               r.sag.seconds,
               r.sag.fit.seconds,
               double(r.sag.fit.rounds)};
  };
  // Interleaved: for each seed, every thread count in turn, so that a slower spell of a shared
  // machine (minutes long, ±15 %) weighs on every row alike rather than on the rows run in it.
  struct Series {
    std::vector<double> seconds, rules, contention, idle, pentatopes, rollbacks, rho, tau, removals,
        speedup;
    std::array<std::vector<double>, 5> insertions;
    std::array<std::vector<double>, refine::kStages> stages;
    std::vector<double> serial;
    std::vector<double> work, rolled_back, waiting;  // thread-seconds of the parallel phases
    std::vector<double> sag_offset, frame_fit, fit_rounds;
    std::vector<std::uint64_t> fingerprints;  // one per seed, in seed order
    // --ceiling: the one-thread runs at once (their median time), the throughput of that many
    // against one alone, and the paired speedup as a share of it; per seed.
    std::vector<double> at_once, ceiling, of_ceiling;
    bool valid = true;
  };
  std::vector<Series> series(threads.size());
  for (int k = 0; k < repeat; ++k) {
    double sequential = 0;  // this seed's time with the first thread count
    for (std::size_t i = 0; i < threads.size(); ++i) {
      const unsigned t = threads[i];
      Series& s = series[i];
      const auto run = bench::run_in_child<Run>(
          [&] { return refine_once(t, seed + static_cast<std::uint64_t>(k)); });
      if (!run) {
        s.valid = false;
        s.fingerprints.push_back(0);  // keeps the list in seed order
        continue;
      }
      if (i == 0) sequential = run->seconds;
      if (sequential > 0) s.speedup.push_back(sequential / run->seconds);
      s.seconds.push_back(run->seconds);
      s.rules.push_back(run->rules_seconds);
      s.contention.push_back(run->contention);
      s.idle.push_back(run->idle);
      s.work.push_back(run->work);
      s.rolled_back.push_back(run->rolled_back);
      s.waiting.push_back(run->contention - run->rolled_back);
      s.pentatopes.push_back(double(run->pentatopes));
      s.rollbacks.push_back(double(run->rollbacks));
      for (int r = 0; r < 5; ++r) s.insertions[r].push_back(double(run->insertions[r]));
      s.removals.push_back(double(run->removals));
      s.rho.push_back(run->rho_max);
      s.tau.push_back(run->tau_min);
      s.valid &= run->valid;
      s.fingerprints.push_back(run->fingerprint);
      refine::StageSeconds stages;
      stages.seconds = run->stages;
      for (int st = 0; st < refine::kStages; ++st) s.stages[st].push_back(run->stages[st]);
      s.serial.push_back(stages.serial() / run->seconds);
      s.sag_offset.push_back(run->sag_offset);
      s.frame_fit.push_back(run->frame_fit);
      s.fit_rounds.push_back(run->fit_rounds);
      // (Against one thread alone: the first row must be one thread.)
      if (ceiling && t > 1 && threads[0] == 1 && sequential > 0) {
        const auto batch = bench::run_in_children_at_once<Run>(
            t, [&](unsigned) { return refine_once(1, seed + static_cast<std::uint64_t>(k)); });
        double runs_per_second = 0;
        std::vector<double> times;
        for (const auto& b : batch)
          if (b) runs_per_second += 1 / b->seconds, times.push_back(b->seconds);
        if (times.size() == t) {
          const double limit = sequential * runs_per_second;
          s.at_once.push_back(median(times));
          s.ceiling.push_back(limit);
          s.of_ceiling.push_back(sequential / run->seconds / limit);
        }
      }
    }
  }
  double reference = 0;
  for (std::size_t i = 0; i < threads.size(); ++i) {
    const unsigned t = threads[i];
    const Series& s = series[i];
    if (s.seconds.empty()) {
      std::printf("| %u | run failed |\n", t);
      continue;
    }
    const double time = median(s.seconds);
    if (reference == 0) reference = time;
    std::printf(
        "| %u | %.0f | %.2f | %.0f | %.2f | %.2f | %.2f | %.0f | %.2f | %.2f | %.0f / %.0f / %.0f "
        "/ %.0f / %.0f | %.0f | %.2f | %.4f | %s |\n",
        t, median(s.pentatopes), time, median(s.pentatopes) / time, reference / time,
        s.speedup.empty() ? 0.0 : median(s.speedup), median(s.rules), median(s.rollbacks),
        median(s.contention), median(s.idle), median(s.insertions[0]), median(s.insertions[1]),
        median(s.insertions[2]), median(s.insertions[3]), median(s.insertions[4]),
        median(s.removals), *std::max_element(s.rho.begin(), s.rho.end()),
        *std::min_element(s.tau.begin(), s.tau.end()), s.valid ? "yes" : "NO");
  }
  // Where the time goes: each stage's median wall-clock seconds (the rules' phases apart), and
  // the share of the run spent in stages that run on one thread (Amdahl's serial fraction).
  std::printf("\nStages, median seconds\n| threads |");
  for (int st = 0; st < refine::kStages; ++st)
    std::printf(" %s%s |", refine::stage_name(static_cast<refine::Stage>(st)),
                refine::runs_on_threads(static_cast<refine::Stage>(st)) ? "" : " (1 thread)");
  std::printf(" serial share |\n|---|");
  for (int st = 0; st <= refine::kStages; ++st) std::printf("---|");
  std::printf("\n");
  for (std::size_t i = 0; i < threads.size(); ++i) {
    if (series[i].seconds.empty()) continue;
    std::printf("| %u |", threads[i]);
    for (int st = 0; st < refine::kStages; ++st)
      std::printf(" %.3f |", median(series[i].stages[st]));
    std::printf(" %.1f %% |\n", 100 * median(series[i].serial));
  }
  // The extraction stage's own steps: the boundary's sag offset, and within it the frames'
  // volume fit (refine/frame_volume_fit.h), which runs in rounds.
  std::printf(
      "\nIn the extraction stage, median seconds\n| threads | sag offset | of which the frames' "
      "fit | fit rounds |\n|---|---|---|---|\n");
  for (std::size_t i = 0; i < threads.size(); ++i) {
    const Series& s = series[i];
    if (s.seconds.empty()) continue;
    std::printf("| %u | %.3f | %.3f | %.0f |\n", threads[i], median(s.sag_offset),
                median(s.frame_fit), median(s.fit_rounds));
  }
  // Where the workers' time goes in the parallel phases (Progress): operations that committed
  // or had nothing to do, operations rolled back, waits for a lock's holder or the contention
  // manager, and time without work; thread-seconds summed over the workers, and the first as
  // a share of threads × the rules' wall clock.
  std::printf(
      "\nWorkers' time in the rules' phases, median thread-seconds\n| threads | work | rolled "
      "back | waiting | idle | work / (threads × rules s) |\n|---|---|---|---|---|---|\n");
  for (std::size_t i = 0; i < threads.size(); ++i) {
    const Series& s = series[i];
    if (s.seconds.empty()) continue;
    std::printf("| %u | %.2f | %.2f | %.2f | %.2f | %.1f %% |\n", threads[i], median(s.work),
                median(s.rolled_back), median(s.waiting), median(s.idle),
                100 * median(s.work) / (threads[i] * median(s.rules)));
  }
  if (ceiling && !series.empty() && !series[0].seconds.empty()) {
    std::printf(
        "\nThe machine's own limit: N one-thread runs of the seed at once, as N independent "
        "processes; ceiling = one run alone × the runs per second of the N\n| threads | one run "
        "alone s | N at once, median s | ceiling speedup | paired speedup | share of the ceiling "
        "|\n|---|---|---|---|---|---|\n");
    for (std::size_t i = 0; i < threads.size(); ++i) {
      const Series& s = series[i];
      if (s.ceiling.empty()) continue;
      std::printf("| %u | %.2f | %.2f | %.2f | %.2f | %.0f %% |\n", threads[i],
                  median(series[0].seconds), median(s.at_once), median(s.ceiling),
                  median(s.speedup), 100 * median(s.of_ceiling));
    }
  }
  // Each run's mesh (bench::mesh_fingerprint): with one thread, a seed fixes the mesh, so two
  // builds that refine alike print the same lines (scripts/mesh_hashes compares them).
  std::printf("\nMesh fingerprints\n| threads | seed | fingerprint |\n|---|---|---|\n");
  for (std::size_t i = 0; i < threads.size(); ++i)
    for (std::size_t k = 0; k < series[i].fingerprints.size(); ++k)
      std::printf("| %u | %llu | %016llx |\n", threads[i],
                  static_cast<unsigned long long>(seed + k),
                  static_cast<unsigned long long>(series[i].fingerprints[k]));
}
