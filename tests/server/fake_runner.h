// A stand-in for run_job in the job manager's tests: it meshes nothing. Each job is known by its
// RefineParams.seed; it reports progress once, then waits until released, all or by seed (or
// asked to stop: Cancelled), and returns "mesh <seed>" as its result. Seed 666 fails. It keeps
// the threads and the thread budget each job was given.
#pragma once

#include <chrono>
#include <condition_variable>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "job_runner.h"

namespace mesh4d::server {

class FakeRunner {
 public:
  static constexpr std::uint64_t kFailingSeed = 666;

  JobRunner runner() {
    return
        [this](const v1::ImageHeader&, const refine::RefineParams& params, const ImagePreparation&,
               std::string_view, refine::ProgressSink& sink) { return run(params, sink); };
  }
  void release() {
    std::lock_guard lock(mu_);
    released_ = true;
    changed_.notify_all();
  }
  void release(std::uint64_t seed) {
    std::lock_guard lock(mu_);
    released_seeds_.insert(seed);
    changed_.notify_all();
  }
  // The threads a job started with, and its thread budget's limit now (0: none).
  unsigned threads(std::uint64_t seed) {
    std::lock_guard lock(mu_);
    return threads_.count(seed) ? threads_[seed] : 0;
  }
  unsigned limit(std::uint64_t seed) {
    std::lock_guard lock(mu_);
    return budgets_.count(seed) && budgets_[seed] ? budgets_[seed]->limit() : 0;
  }
  // Waits until `n` jobs have started; false after 10 s.
  bool wait_started(std::size_t n) {
    std::unique_lock lock(mu_);
    return changed_.wait_for(lock, std::chrono::seconds(10), [&] { return started_.size() >= n; });
  }
  std::vector<std::uint64_t> started() {
    std::lock_guard lock(mu_);
    return started_;
  }

 private:
  JobOutcome run(const refine::RefineParams& params, refine::ProgressSink& sink) {
    {
      std::lock_guard lock(mu_);
      started_.push_back(params.seed);
      threads_[params.seed] = params.threads;
      budgets_[params.seed] = params.thread_budget;
      changed_.notify_all();
    }
    refine::Progress p;
    p.vertices = params.seed;
    sink.on_progress(p);
    std::unique_lock lock(mu_);
    while (!released_ && !released_seeds_.count(params.seed)) {
      if (sink.should_abort()) throw refine::Cancelled();
      changed_.wait_for(lock, std::chrono::milliseconds(5));
    }
    if (params.seed == kFailingSeed) throw std::runtime_error("planted failure");
    JobOutcome out;
    out.mesh = "mesh " + std::to_string(params.seed);
    out.stats.pentatopes = params.seed;
    return out;
  }

  std::mutex mu_;
  std::condition_variable changed_;
  bool released_ = false;
  std::vector<std::uint64_t> started_;
  std::set<std::uint64_t> released_seeds_;
  std::map<std::uint64_t, unsigned> threads_;
  std::map<std::uint64_t, std::shared_ptr<const refine::ThreadBudget>> budgets_;
};

}  // namespace mesh4d::server
