// The job service behind every transport: a bounded FIFO queue, a fixed number of runner
// threads, the durable store, and each job's event log for watchers. One mutex guards it all;
// the engine runs outside it.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "core_allocator.h"
#include "job_runner.h"
#include "job_store.h"
#include "mesh4d/v1/mesh4d.pb.h"

namespace mesh4d::server {

struct ManagerConfig {
  unsigned running_jobs = 1;      // jobs refined at once
  unsigned threads_per_job = 1;   // cap on RefineParams.threads
  unsigned cores = 1;             // shared among the running jobs (core_allocator.h)
  unsigned max_queued_jobs = 16;  // QUEUED jobs beyond this are refused
  std::uint64_t max_image_bytes = 2ull << 30;
  std::uint64_t max_vertex_budget = 20'000'000;
  std::chrono::seconds retention{0};  // finished jobs are deleted after this; 0: kept
};

/// What the manager tells about jobs (the metrics and logs hook in here).
struct JobObserver {
  virtual ~JobObserver() = default;
  virtual void on_state(const v1::Job& /*job*/, v1::JobState /*previous*/) {}
  virtual void on_bytes_received(std::uint64_t /*bytes*/) {}
  virtual void on_bytes_sent(std::uint64_t /*bytes*/) {}
};

class JobManager {
 public:
  /// `runner` meshes each job (run_job; tests give a stand-in).
  JobManager(JobStore& store, ManagerConfig config, JobObserver* observer = nullptr,
             JobRunner runner = run_job);
  ~JobManager();  // stop()

  /// Takes no more work, at once: no queued job starts, a running one stops at its next check
  /// and stays RUNNING on disk (it runs again at restart), every watch ends (server_stopping).
  /// Returns when the runners have ended. Idempotent.
  void stop();

  /// Loads the store: finished jobs are served again, queued and running ones re-queued.
  /// Then starts the runners. Returns messages about records it could not read.
  std::vector<std::string> start();

  struct Submitted {
    v1::Job job;
    bool deduplicated = false;
  };
  /// Validates, stores durably, then queues. Throws wire::ServiceError.
  Submitted submit(const v1::JobSpec& spec, std::string data);
  /// The largest label data submit() accepts: at least one byte per voxel, so a file whose
  /// header announces more voxels can be refused before it is read.
  std::uint64_t max_image_bytes() const { return config_.max_image_bytes; }

  v1::Job get(const std::string& id) const;
  v1::Job cancel(const std::string& id);
  void remove(const std::string& id);

  struct Page {
    std::vector<v1::Job> jobs;
    std::string next_token;
  };
  Page list(v1::JobState state, std::uint32_t page_size, const std::string& token) const;

  struct Result {
    v1::Job job;
    std::string mesh;
  };
  /// A SUCCEEDED job's mesh, checked against the checksum taken when it was written. A result
  /// that is missing, unreadable or altered throws wire::ServiceError(data_loss), and the job
  /// becomes FAILED with the reason.
  Result result(const std::string& id);

  /// How a watch ended: the job reached a final state, it was deleted, or the watcher left
  /// (on_event returned false, or `cancelled` true).
  enum class WatchEnd { job_ended, job_deleted, watcher_left, server_stopping };
  /// Follows a job for every face: with `after` 0, its whole state first (a snapshot event
  /// numbered with its latest event), then each event after it, until the job ends; with
  /// `after` the sequence of the last event a watcher saw, the events after that one (a new
  /// snapshot when the log no longer holds them). `cancelled` is asked between events, at
  /// least every half second. Throws ServiceError(not_found) for an unknown job.
  WatchEnd watch(const std::string& id, std::uint64_t after,
                 const std::function<bool(const v1::JobEvent&)>& on_event,
                 const std::function<bool()>& cancelled) const;

  /// Counts by state, and the queue depth (for metrics).
  std::map<v1::JobState, std::size_t> count_by_state() const;

 private:
  struct Entry {
    v1::Job job;
    std::deque<v1::JobEvent> events;
    std::uint64_t last_sequence = 0;
    std::atomic<bool> cancel{false};
  };
  class Sink;

  // The whole job as an event numbered with its latest event.
  v1::JobEvent snapshot(const std::string& id) const;
  // The events after `after` (waiting until `deadline` when there are none), or a new snapshot
  // when the log no longer holds them. False when the job is gone.
  bool wait(const std::string& id, std::uint64_t after,
            std::chrono::steady_clock::time_point deadline, std::vector<v1::JobEvent>* out) const;
  Entry& find(const std::string& id) const;      // throws not_found; with mu_ held
  void publish(Entry& e, v1::JobEvent event);    // with mu_ held
  void set_state(Entry& e, v1::JobState state);  // with mu_ held: persists, publishes
  void trim_ended_logs();                        // with mu_ held
  // What is wrong with a job's stored result ("" when it is whole); `mesh` receives it.
  std::string result_problem(const v1::Job& job, std::string* mesh) const;
  // A message for clients: the data directory's path (the server's own) as <data-dir>; the
  // server's log keeps it whole.
  std::string without_paths(std::string message) const;
  // A SUCCEEDED job whose result is lost: FAILED, saying why (with mu_ held).
  void lose_result(Entry& e, const std::string& problem);
  v1::Job view(const Entry& e) const;  // with queue_position filled in
  void runner_loop();
  void run(const std::string& id);
  void sweep_expired();  // with mu_ held

  JobStore& store_;
  ManagerConfig config_;
  JobObserver* observer_;
  JobRunner runner_;
  CoreAllocator cores_;
  mutable std::mutex mu_;
  mutable std::condition_variable changed_;  // any event, queue change or stop
  std::map<std::string, std::unique_ptr<Entry>> jobs_;
  std::map<std::string, std::string> by_request_id_;
  std::deque<std::string> queue_;
  // Ended jobs whose event log is still whole, oldest first: trimmed once watchers have had
  // time to read it (trim_ended_logs).
  std::deque<std::pair<std::chrono::steady_clock::time_point, std::string>> ended_logs_;
  std::atomic<bool> stopping_{false};
  std::vector<std::thread> runners_;
};

}  // namespace mesh4d::server
