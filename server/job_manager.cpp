#include "job_manager.h"

#include <google/protobuf/util/message_differencer.h>
#include <google/protobuf/util/time_util.h>
#include <malloc.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <sstream>

#include "domain/periodic_time.h"
#include "domain/segmentation_cleanup.h"
#include "domain/time_extension.h"
#include "domain/time_scale.h"
#include "job_log.h"
#include "job_runner.h"
#include "proto_convert.h"
#include "refine/refiner.h"
#include "wire/digest.h"
#include "wire/service_error.h"
#include "wire/upload_codec.h"

namespace mesh4d::server {
namespace {

using google::protobuf::util::TimeUtil;

constexpr std::size_t kEventLog = 512;  // events kept per job for watchers that fall behind
// The time to the nanosecond: Debian's protobuf (3.21) takes TimeUtil::GetCurrentTime() from
// time(), in whole seconds, which summed 15 ms jobs as 0 or 1 s and left jobs created in one
// second in no order.
google::protobuf::Timestamp now() {
  return TimeUtil::NanosecondsToTimestamp(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                              std::chrono::system_clock::now().time_since_epoch())
                                              .count());
}

// How far a restarted server moves each job's event numbers past the last one it wrote.
constexpr std::uint64_t kSequenceGapAtRestart = std::uint64_t{1} << 32;
constexpr auto kWatchPoll = std::chrono::milliseconds(500);  // watch() asks `cancelled` this often

bool terminal(v1::JobState s) {
  return s == v1::JOB_STATE_SUCCEEDED || s == v1::JOB_STATE_FAILED || s == v1::JOB_STATE_CANCELLED;
}

std::string new_job_id() {
  static std::mutex mu;
  static std::mt19937_64 rng{std::random_device{}()};
  std::lock_guard lock(mu);
  char id[20];
  std::snprintf(id, sizeof id, "j%016llx", static_cast<unsigned long long>(rng()));
  return id;
}

// Listing order: creation time, then id; the page token is the last key returned.
std::string list_key(const v1::Job& job) {
  char key[64];
  std::snprintf(key, sizeof key, "%020lld.%09d/", static_cast<long long>(job.created().seconds()),
                job.created().nanos());
  return key + job.id();
}

[[noreturn]] void not_found(const std::string& id) {
  throw wire::ServiceError(wire::ErrorCode::not_found, "no job with id '" + id + "'");
}

}  // namespace

class JobManager::Sink : public refine::ProgressSink {
 public:
  Sink(JobManager& manager, Entry& entry) : manager_(manager), entry_(entry) {}
  void on_progress(const refine::Progress& p) override {
    std::lock_guard lock(manager_.mu_);
    *entry_.job.mutable_progress() = to_proto(p);
    v1::JobEvent event;
    *event.mutable_progress() = entry_.job.progress();
    manager_.publish(entry_, std::move(event));
  }
  bool should_abort() override { return entry_.cancel || manager_.stopping_; }

 private:
  JobManager& manager_;
  Entry& entry_;
};

JobManager::JobManager(JobStore& store, ManagerConfig config, JobObserver* observer,
                       JobRunner runner)
    : store_(store),
      config_(config),
      observer_(observer),
      runner_(std::move(runner)),
      cores_(config.cores, config.threads_per_job, config.running_jobs) {}

JobManager::~JobManager() {
  stop();
}

void JobManager::stop() {
  {
    std::lock_guard lock(mu_);
    stopping_ = true;
  }
  changed_.notify_all();
  for (auto& t : runners_)
    if (t.joinable()) t.join();
}

std::vector<std::string> JobManager::start() {
  std::vector<std::string> problems;
  auto jobs = store_.load_all(&problems);
  std::sort(jobs.begin(), jobs.end(),
            [](const v1::Job& a, const v1::Job& b) { return list_key(a) < list_key(b); });
  {
    std::lock_guard lock(mu_);
    for (auto& job : jobs) {
      auto e = std::make_unique<Entry>();
      if (job.state() == v1::JOB_STATE_SUCCEEDED) {
        std::string mesh;
        if (job.result_sha256().empty()) {
          // A record from before results had checksums: the file as it is now is trusted.
          try {
            job.set_result_sha256(wire::sha256(store_.read_result(job.id())));
            store_.save(job);
          } catch (const std::exception&) {
          }
        }
        if (const std::string problem = result_problem(job, &mesh); !problem.empty()) {
          problems.push_back("job " + job.id() + ": " + problem + "; it is now FAILED");
          job.set_error(problem + " (submit the job again)");
          job.set_state(v1::JOB_STATE_FAILED);
          store_.save(job);
        }
      }
      if (!terminal(job.state())) {
        // Queued, or running when the server stopped: runs again from the start.
        if (job.state() != v1::JOB_STATE_QUEUED) {
          job.set_state(v1::JOB_STATE_QUEUED);
          job.clear_progress();
          job.clear_started();
          store_.save(job);
        }
        queue_.push_back(job.id());
      }
      if (!job.request_id().empty()) by_request_id_[job.request_id()] = job.id();
      e->last_sequence = job.last_event_sequence() + kSequenceGapAtRestart;
      if (observer_) observer_->on_state(job, v1::JOB_STATE_UNSPECIFIED);
      e->job = std::move(job);
      jobs_[e->job.id()] = std::move(e);
    }
  }
  for (unsigned i = 0; i < std::max(1u, config_.running_jobs); ++i)
    runners_.emplace_back([this] { runner_loop(); });
  return problems;
}

JobManager::Submitted JobManager::submit(const v1::JobSpec& spec, std::string data) {
  if (!spec.has_image())
    throw wire::ServiceError(wire::ErrorCode::invalid_argument, "spec.image is missing");
  const std::uint64_t bytes = wire::check_header(spec.image());
  if (bytes > config_.max_image_bytes) {
    std::ostringstream m;
    m << "the image has " << bytes << " bytes; this server accepts at most "
      << config_.max_image_bytes;
    throw wire::ServiceError(wire::ErrorCode::resource_exhausted, m.str());
  }
  refine::RefineParams params = to_engine(spec.params());
  // An unset budget is the engine's default within this server's limit; only an explicit one
  // over the limit is refused.
  if (spec.params().vertex_budget() == 0)
    params.vertex_budget = std::min(params.vertex_budget, config_.max_vertex_budget);
  try {
    refine::validate(params);
  } catch (const refine::ParamError& e) {
    throw wire::ServiceError(wire::ErrorCode::invalid_argument, std::string("params: ") + e.what());
  }
  if (spec.params().extend_time_frames() > domain::kMaxTimeExtension) {
    std::ostringstream m;
    m << "params.extend_time_frames " << spec.params().extend_time_frames() << " is over "
      << domain::kMaxTimeExtension;
    throw wire::ServiceError(wire::ErrorCode::invalid_argument, m.str());
  }
  const bool periodic = periodic_time(spec.params());  // refuses an unknown topology
  if (periodic && spec.params().extend_time_frames() != 0)
    throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                             "params.extend_time_frames lengthens an open mesh at its ends; a "
                             "periodic one (time_topology periodic) has none: leave it 0");
  if (periodic && spec.image().dims().t() < 2) {
    std::ostringstream m;
    m << "time_topology periodic needs at least two frames; the image has "
      << spec.image().dims().t();
    throw wire::ServiceError(wire::ErrorCode::invalid_argument, m.str());
  }
  const double time_scale = spec.params().time_scale();
  if (!std::isfinite(time_scale) || time_scale < 0) {
    std::ostringstream m;
    m << "params.time_scale " << time_scale
      << " must be finite and > 0 (the length of one frame along t), or 0 to choose it from the "
         "data";
    throw wire::ServiceError(wire::ErrorCode::invalid_argument, m.str());
  }
  if (params.vertex_budget > config_.max_vertex_budget) {
    std::ostringstream m;
    m << "params.vertex_budget " << params.vertex_budget << " is over this server's limit of "
      << config_.max_vertex_budget;
    throw wire::ServiceError(wire::ErrorCode::resource_exhausted, m.str());
  }
  // 0: the job's share of the cores when it starts (core_allocator.h).
  const unsigned threads = std::min(spec.params().threads(), config_.threads_per_job);
  // The parameters as the job keeps them, the server's defaults filled in.
  v1::RefineParams stored = to_proto(params, threads);
  stored.set_extend_time_frames(spec.params().extend_time_frames());
  stored.set_strict(spec.params().strict());
  stored.set_min_island_voxels(spec.params().has_min_island_voxels()
                                   ? spec.params().min_island_voxels()
                                   : domain::kDefaultMinIslandVoxels);
  stored.set_time_scale(time_scale);  // an automatic one is filled in once the image is read
  stored.set_time_topology(periodic ? v1::TIME_TOPOLOGY_PERIODIC : v1::TIME_TOPOLOGY_OPEN);
  // A retry (same request_id) gets the first job back, but only when it asks for the same mesh
  // (an automatic time scale asks for the one the first job chose from the same image).
  auto duplicate = [&]() -> const Entry* {
    if (spec.request_id().empty()) return nullptr;
    const auto it = by_request_id_.find(spec.request_id());
    if (it == by_request_id_.end()) return nullptr;
    const Entry& e = find(it->second);
    using google::protobuf::util::MessageDifferencer;
    const bool same_image = MessageDifferencer::Equals(e.job.image(), spec.image());
    v1::RefineParams asked = stored;
    if (time_scale == 0) asked.set_time_scale(e.job.params().time_scale());
    if (!same_image || !MessageDifferencer::Equals(e.job.params(), asked))
      throw wire::ServiceError(wire::ErrorCode::already_exists,
                               "request_id '" + spec.request_id() + "' was already used for job " +
                                   e.job.id() + " with a different " +
                                   (same_image ? "parameters" : "image") +
                                   "; a new submission needs a new request_id");
    return &e;
  };
  {
    std::lock_guard lock(mu_);
    if (const Entry* e = duplicate()) return {view(*e), true};
  }
  std::vector<std::string> warnings;
  // Size, checksum and labels; throws.
  const domain::LabelImage4 image = wire::decode_upload(spec.image(), data, &warnings);
  if (periodic) domain::drop_time_padding_warnings(warnings);
  if (time_scale == 0)
    stored.set_time_scale(domain::automatic_time_scale(image, params.delta, periodic));

  std::lock_guard lock(mu_);
  if (const Entry* e = duplicate()) return {view(*e), true};  // a concurrent retry won
  if (queue_.size() >= config_.max_queued_jobs) {
    std::ostringstream m;
    m << "the queue is full (" << queue_.size() << " jobs waiting); retry later";
    throw wire::ServiceError(wire::ErrorCode::resource_exhausted, m.str());
  }
  auto e = std::make_unique<Entry>();
  v1::Job& job = e->job;
  job.set_id(new_job_id());
  job.set_state(v1::JOB_STATE_QUEUED);
  job.set_name(spec.name());
  job.set_request_id(spec.request_id());
  *job.mutable_image() = spec.image();
  *job.mutable_params() = stored;
  *job.mutable_created() = now();
  for (auto& w : warnings) job.add_warnings(w);
  try {
    store_.create(job, data);
  } catch (const std::exception& ex) {
    store_.remove(job.id());
    log_job(spdlog::level::err, job.id(), "cannot store the job: {}", ex.what());
    throw wire::ServiceError(wire::ErrorCode::internal,
                             "the server cannot store the job: " + without_paths(ex.what()));
  }
  if (observer_) observer_->on_bytes_received(data.size());
  const std::string id = job.id();
  if (!job.request_id().empty()) by_request_id_[job.request_id()] = id;
  queue_.push_back(id);
  cores_.queue_changed(queue_.size());
  Entry& entry = *e;
  jobs_[id] = std::move(e);
  v1::JobEvent event;
  event.set_state(v1::JOB_STATE_QUEUED);
  publish(entry, std::move(event));
  if (observer_) observer_->on_state(entry.job, v1::JOB_STATE_UNSPECIFIED);
  log_job(spdlog::level::info, id, "queued ({} bytes, delta {})", data.size(), params.delta);
  return {view(entry), false};
}

JobManager::Entry& JobManager::find(const std::string& id) const {
  const auto it = jobs_.find(id);
  if (it == jobs_.end()) not_found(id);
  return *it->second;
}

v1::Job JobManager::view(const Entry& e) const {
  v1::Job job = e.job;
  if (job.state() == v1::JOB_STATE_QUEUED) {
    const auto it = std::find(queue_.begin(), queue_.end(), job.id());
    job.set_queue_position(static_cast<std::uint32_t>(it - queue_.begin()));
  }
  return job;
}

void JobManager::publish(Entry& e, v1::JobEvent event) {
  event.set_sequence(++e.last_sequence);
  *event.mutable_time() = now();
  e.events.push_back(std::move(event));
  if (e.events.size() > kEventLog) e.events.pop_front();
  changed_.notify_all();
}

void JobManager::set_state(Entry& e, v1::JobState state) {
  const v1::JobState previous = e.job.state();
  e.job.set_state(state);
  if (state == v1::JOB_STATE_RUNNING) *e.job.mutable_started() = now();
  if (terminal(state)) *e.job.mutable_finished() = now();
  e.job.set_last_event_sequence(e.last_sequence + 1);  // the state event published below
  try {
    store_.save(e.job);
  } catch (const std::exception& ex) {
    log_job(spdlog::level::err, e.job.id(), "cannot store its state: {}", ex.what());
  }
  v1::JobEvent event;
  event.set_state(state);
  publish(e, std::move(event));
  if (terminal(state)) ended_logs_.emplace_back(std::chrono::steady_clock::now(), e.job.id());
  trim_ended_logs();
  if (observer_) observer_->on_state(e.job, previous);
}

// An ended job's progress is history: a watcher that falls behind after a while gets the
// snapshot, which holds it all. Only the final statistics and the state stay in the log, so that
// a server that keeps thousands of ended jobs keeps little for each; watchers that are reading
// as the job ends have kEndedLogGrace to finish.
void JobManager::trim_ended_logs() {
  constexpr auto kEndedLogGrace = std::chrono::seconds(10);
  const auto now = std::chrono::steady_clock::now();
  while (!ended_logs_.empty() && now - ended_logs_.front().first > kEndedLogGrace) {
    if (const auto it = jobs_.find(ended_logs_.front().second); it != jobs_.end()) {
      auto& events = it->second->events;
      while (events.size() > 2) events.pop_front();
      events.shrink_to_fit();
    }
    ended_logs_.pop_front();
  }
}

v1::Job JobManager::get(const std::string& id) const {
  std::lock_guard lock(mu_);
  return view(find(id));
}

v1::Job JobManager::cancel(const std::string& id) {
  std::lock_guard lock(mu_);
  Entry& e = find(id);
  if (e.job.state() == v1::JOB_STATE_QUEUED) {
    queue_.erase(std::find(queue_.begin(), queue_.end(), id));
    cores_.queue_changed(queue_.size());
    e.job.set_error("cancelled by request while queued");
    set_state(e, v1::JOB_STATE_CANCELLED);
    log_job(spdlog::level::info, id, "cancelled while queued");
  } else if (e.job.state() == v1::JOB_STATE_RUNNING) {
    e.cancel = true;  // the runner stops at its next check and records CANCELLED
  }
  return view(e);
}

void JobManager::remove(const std::string& id) {
  std::lock_guard lock(mu_);
  Entry& e = find(id);
  if (e.job.state() == v1::JOB_STATE_RUNNING)
    throw wire::ServiceError(
        wire::ErrorCode::failed_precondition,
        "job " + id + " is running: cancel it, then delete it once it has stopped");
  if (e.job.state() == v1::JOB_STATE_QUEUED) {
    queue_.erase(std::find(queue_.begin(), queue_.end(), id));
    cores_.queue_changed(queue_.size());
  }
  if (!e.job.request_id().empty()) by_request_id_.erase(e.job.request_id());
  store_.remove(id);
  jobs_.erase(id);
  changed_.notify_all();
  log_job(spdlog::level::info, id, "deleted");
}

JobManager::Page JobManager::list(v1::JobState state, std::uint32_t page_size,
                                  const std::string& token) const {
  constexpr std::uint32_t kDefaultPage = 50, kMaxPage = 1000;
  if (!token.empty() && (token.size() < 32 || token[20] != '.' || token[30] != '/'))
    throw wire::ServiceError(wire::ErrorCode::invalid_argument,
                             "page_token is not one this server gave");
  const std::uint32_t size = page_size == 0 ? kDefaultPage : std::min(page_size, kMaxPage);
  std::lock_guard lock(mu_);
  std::vector<std::pair<std::string, const Entry*>> matching;
  for (const auto& [id, e] : jobs_)
    if (state == v1::JOB_STATE_UNSPECIFIED || e->job.state() == state) {
      std::string key = list_key(e->job);
      if (key > token) matching.emplace_back(std::move(key), e.get());
    }
  std::sort(matching.begin(), matching.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  Page page;
  for (std::size_t i = 0; i < matching.size() && i < size; ++i)
    page.jobs.push_back(view(*matching[i].second));
  if (matching.size() > size) page.next_token = matching[size - 1].first;
  return page;
}

std::string JobManager::result_problem(const v1::Job& job, std::string* mesh) const {
  try {
    *mesh = store_.read_result(job.id());
  } catch (const std::exception&) {
    return "the stored result is missing or unreadable";
  }
  if (wire::sha256(*mesh) != job.result_sha256())
    return "the stored result is corrupt: its SHA-256 is not the one taken when it was written";
  return "";
}

std::string JobManager::without_paths(std::string message) const {
  const std::string root = store_.root().string();
  for (std::size_t at; !root.empty() && (at = message.find(root)) != std::string::npos;)
    message.replace(at, root.size(), "<data-dir>");
  return message;
}

void JobManager::lose_result(Entry& e, const std::string& problem) {
  log_job(spdlog::level::err, e.job.id(), "{}; the job is now FAILED", problem);
  e.job.set_error(problem + " (submit the job again)");
  set_state(e, v1::JOB_STATE_FAILED);
}

JobManager::Result JobManager::result(const std::string& id) {
  Result r;
  {
    std::lock_guard lock(mu_);
    const Entry& e = find(id);
    if (e.job.state() == v1::JOB_STATE_CANCELLED)
      throw wire::ServiceError(
          wire::ErrorCode::cancelled,
          "job " + id + " was cancelled (" + e.job.error() + "): it has no result");
    if (e.job.state() != v1::JOB_STATE_SUCCEEDED)
      throw wire::ServiceError(wire::ErrorCode::failed_precondition,
                               "job " + id + " is " + v1::JobState_Name(e.job.state()) +
                                   ": a result exists once it has SUCCEEDED");
    r.job = view(e);
  }
  // Read and hashed outside the lock: a large mesh must not stall the other calls.
  const std::string problem = result_problem(r.job, &r.mesh);
  if (problem.empty()) return r;
  std::lock_guard lock(mu_);
  if (const auto it = jobs_.find(id);
      it != jobs_.end() && it->second->job.state() == v1::JOB_STATE_SUCCEEDED)
    lose_result(*it->second, problem);
  throw wire::ServiceError(wire::ErrorCode::data_loss, "job " + id + ": " + problem);
}

v1::JobEvent JobManager::snapshot(const std::string& id) const {
  std::lock_guard lock(mu_);
  const Entry& e = find(id);
  v1::JobEvent event;
  event.set_sequence(e.last_sequence);
  *event.mutable_time() = now();
  *event.mutable_snapshot() = view(e);
  return event;
}

bool JobManager::wait(const std::string& id, std::uint64_t after,
                      std::chrono::steady_clock::time_point deadline,
                      std::vector<v1::JobEvent>* out) const {
  std::unique_lock lock(mu_);
  while (true) {
    const auto it = jobs_.find(id);
    if (it == jobs_.end()) return false;
    const Entry& e = *it->second;
    if (e.last_sequence > after) {
      if (e.events.empty() || e.events.front().sequence() > after + 1) {
        v1::JobEvent event;  // the log lost some: start over from a snapshot
        event.set_sequence(e.last_sequence);
        *event.mutable_time() = now();
        *event.mutable_snapshot() = view(e);
        out->push_back(std::move(event));
      } else {
        for (const auto& event : e.events)
          if (event.sequence() > after) out->push_back(event);
      }
      return true;
    }
    if (stopping_) return true;  // the watch ends at its next check
    if (changed_.wait_until(lock, deadline) == std::cv_status::timeout) return true;
  }
}

JobManager::WatchEnd JobManager::watch(const std::string& id, std::uint64_t after,
                                       const std::function<bool(const v1::JobEvent&)>& on_event,
                                       const std::function<bool()>& cancelled) const {
  const auto ends = [](const v1::JobEvent& e) {
    return (e.has_snapshot() && terminal(e.snapshot().state())) ||
           (e.event_case() == v1::JobEvent::kState && terminal(e.state()));
  };
  const v1::JobEvent first = snapshot(id);  // throws not_found
  std::uint64_t seen = after;
  if (after == 0 || after > first.sequence()) {
    if (!on_event(first)) return WatchEnd::watcher_left;
    if (ends(first)) return WatchEnd::job_ended;
    seen = first.sequence();
  } else if (after == first.sequence() && ends(first)) {
    return WatchEnd::job_ended;  // the watcher saw the last event already
  }
  std::vector<v1::JobEvent> events;
  while (!cancelled()) {
    if (stopping_) return WatchEnd::server_stopping;
    events.clear();
    const auto deadline = std::chrono::steady_clock::now() + kWatchPoll;
    if (!wait(id, seen, deadline, &events)) return WatchEnd::job_deleted;
    for (const auto& e : events) {
      if (!on_event(e)) return WatchEnd::watcher_left;
      seen = e.sequence();
      if (ends(e)) return WatchEnd::job_ended;
    }
  }
  return WatchEnd::watcher_left;
}

std::map<v1::JobState, std::size_t> JobManager::count_by_state() const {
  std::lock_guard lock(mu_);
  std::map<v1::JobState, std::size_t> counts;
  for (const auto& [id, e] : jobs_) ++counts[e->job.state()];
  return counts;
}

void JobManager::sweep_expired() {
  if (config_.retention.count() <= 0) return;
  const auto time_now = now();
  std::vector<std::string> expired;
  for (const auto& [id, e] : jobs_)
    if (terminal(e->job.state()) &&
        TimeUtil::DurationToSeconds(time_now - e->job.finished()) > config_.retention.count())
      expired.push_back(id);
  for (const auto& id : expired) {
    const Entry& e = *jobs_[id];
    if (!e.job.request_id().empty()) by_request_id_.erase(e.job.request_id());
    store_.remove(id);
    jobs_.erase(id);
    log_job(spdlog::level::info, id, "deleted: older than the retention");
  }
  if (!expired.empty()) changed_.notify_all();
}

void JobManager::runner_loop() {
  std::unique_lock lock(mu_);
  while (!stopping_) {
    if (queue_.empty()) {
      changed_.wait_for(lock, std::chrono::seconds(30));
      sweep_expired();
      trim_ended_logs();
      continue;
    }
    const std::string id = queue_.front();
    queue_.pop_front();
    lock.unlock();
    run(id);
    // A job's triangulation is millions of small blocks, freed in an order that leaves holes in
    // the heap; glibc keeps such memory unless asked. The soak test (tests/e2e/soak_test.cpp)
    // saw 33 MiB grow to 156 MiB in a minute of small jobs without this, and stay there.
    ::malloc_trim(0);
    lock.lock();
  }
}

void JobManager::run(const std::string& id) {
  Entry* entry;
  v1::ImageHeader header;
  refine::RefineParams params;
  ImagePreparation preparation;
  bool strict = false;
  CoreAllocator::Share share;
  {
    std::lock_guard lock(mu_);
    entry = &find(id);
    set_state(*entry, v1::JOB_STATE_RUNNING);
    header = entry->job.image();
    params = to_engine(entry->job.params());
    preparation.extend_time_frames = entry->job.params().extend_time_frames();
    preparation.min_island_voxels = entry->job.params().min_island_voxels();
    preparation.time_scale = entry->job.params().time_scale();
    preparation.periodic = periodic_time(entry->job.params());
    strict = entry->job.params().strict();
    share = cores_.start(entry->job.params().threads(), queue_.size());
  }
  params.threads = share.threads;
  params.thread_budget = share.budget;
  // Whatever way the job ends, its cores go to the others: before its end state is published
  // (now(), under mu_), so that whoever sees the job ended sees the others' new shares too.
  struct Release {
    JobManager& manager;
    const CoreAllocator::Share& share;
    bool done = false;
    void now() {
      if (!done) manager.cores_.finish(share, manager.queue_.size());
      done = true;
    }
    ~Release() {
      std::lock_guard lock(manager.mu_);
      now();
    }
  } release{*this, share};
  log_job(spdlog::level::info, id,
          "running: delta {}, time scale {} per frame, {} time, {} threads", params.delta,
          preparation.time_scale, preparation.periodic ? "periodic" : "open", share.threads);
  Sink sink(*this, *entry);
  std::string error;
  v1::JobState end = v1::JOB_STATE_FAILED;
  try {
    const std::string input = store_.read_input(id);
    JobOutcome outcome = runner_(header, params, preparation, input, sink);
    // A mesh without pentatopes is no result, whatever made it so.
    if (outcome.stats.pentatopes == 0) {
      std::ostringstream why;
      why << "the mesh is empty: no pentatope lies in the object at delta " << params.delta
          << " (a delta larger than the object, or an object thinner than delta in every "
             "frame, as a single frame is in time: use a smaller delta, or extend_time_frames)";
      throw std::runtime_error(why.str());
    }
    const std::vector<std::string> defects = outcome.certificate.defects();
    if (strict && !defects.empty()) {
      // The certificate goes with the failed job, for the user to see why.
      std::lock_guard lock(mu_);
      *entry->job.mutable_stats() = to_proto(outcome.stats);
      add_certificate(outcome.certificate, entry->job.mutable_stats());
      std::string why = "strict: the fidelity certificate found defects";
      for (const auto& d : defects) why += "; " + d;
      throw std::runtime_error(why);
    }
    store_.save_result(id, outcome.mesh);
    const std::string checksum = wire::sha256(outcome.mesh);
    std::lock_guard lock(mu_);
    entry->job.set_result_sha256(checksum);
    *entry->job.mutable_stats() = to_proto(outcome.stats);
    add_certificate(outcome.certificate, entry->job.mutable_stats());
    entry->job.clear_warnings();
    for (auto& w : outcome.warnings) entry->job.add_warnings(w);
    v1::JobEvent finished;
    *finished.mutable_finished() = entry->job.stats();
    publish(*entry, std::move(finished));
    release.now();
    set_state(*entry, v1::JOB_STATE_SUCCEEDED);
    log_job(spdlog::level::info, id,
            "succeeded: {} pentatopes in {:.2f} s ({} relabeled to close pinches where labels "
            "meet)",
            outcome.stats.pentatopes, outcome.stats.elapsed_seconds, outcome.relabeled);
    return;
  } catch (const refine::Cancelled&) {
    std::lock_guard lock(mu_);
    if (stopping_ && !entry->cancel) {
      log_job(spdlog::level::info, id, "interrupted by shutdown: it runs again at restart");
      return;  // still RUNNING on disk
    }
    error = "cancelled by request while running";
    end = v1::JOB_STATE_CANCELLED;
  } catch (const std::exception& e) {
    error = e.what();
  }
  std::lock_guard lock(mu_);
  log_job(spdlog::level::debug, id, "error in full: {}", error);
  error = without_paths(error);
  entry->job.set_error(error);
  release.now();
  set_state(*entry, end);
  log_job(spdlog::level::info, id, "{}: {}", v1::JobState_Name(end), error);
}

}  // namespace mesh4d::server
