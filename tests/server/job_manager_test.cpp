// The job manager with a stand-in runner (fake_runner.h): the queue's order, the states a job
// goes through and what a watcher sees of them, cancellation, failure, the queue's limit,
// request ids, and recovery from the store after a restart.
#include "job_manager.h"

#include <gtest/gtest.h>

#include <chrono>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include "../e2e/process.h"
#include "domain/phantoms.h"
#include "fake_runner.h"
#include "wire/service_error.h"
#include "wire/upload_codec.h"

namespace mesh4d::server {
namespace {

using Clock = std::chrono::steady_clock;

// A small valid upload; the seed tells the jobs apart.
struct Upload {
  v1::JobSpec spec;
  std::string data;
};
Upload upload(std::uint64_t seed, const std::string& request_id = "", int radius = 3) {
  Upload u;
  u.data = wire::encode_upload(domain::hypersphere_phantom({10, 10, 10, 10}, {1, 1, 1, 1}, radius),
                               u.spec.mutable_image());
  u.spec.mutable_params()->set_seed(seed);
  u.spec.set_request_id(request_id);
  return u;
}

// The job's state once it is `state`; the last state seen after 10 s otherwise.
v1::Job wait_for_state(const JobManager& jobs, const std::string& id, v1::JobState state) {
  const auto end = Clock::now() + std::chrono::seconds(10);
  v1::Job job = jobs.get(id);
  while (job.state() != state && Clock::now() < end) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    job = jobs.get(id);
  }
  return job;
}

wire::ErrorCode refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const wire::ServiceError& e) {
    return e.code();
  }
  ADD_FAILURE() << "not refused";
  return wire::ErrorCode::internal;
}

class JobManagerTest : public ::testing::Test {
 protected:
  std::string dir_ = mesh4d::testing::make_temp_dir("mesh4d-manager");
  JobStore store_{dir_};
  FakeRunner fake_;
};

TEST_F(JobManagerTest, RunsJobsInTheOrderTheyCameAndServesTheirResults) {
  JobManager jobs(store_, {}, nullptr, fake_.runner());
  jobs.start();
  std::vector<std::string> ids;
  for (std::uint64_t seed : {11, 12, 13})
    ids.push_back(jobs.submit(upload(seed).spec, upload(seed).data).job.id());
  ASSERT_TRUE(fake_.wait_started(1));
  EXPECT_EQ(wait_for_state(jobs, ids[0], v1::JOB_STATE_RUNNING).state(), v1::JOB_STATE_RUNNING);
  EXPECT_EQ(jobs.get(ids[1]).state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(jobs.get(ids[1]).queue_position(), 0u);
  EXPECT_EQ(jobs.get(ids[2]).queue_position(), 1u);
  fake_.release();
  for (const auto& id : ids)
    EXPECT_EQ(wait_for_state(jobs, id, v1::JOB_STATE_SUCCEEDED).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(fake_.started(), (std::vector<std::uint64_t>{11, 12, 13}));
  EXPECT_EQ(jobs.result(ids[1]).mesh, "mesh 12");
  EXPECT_EQ(jobs.result(ids[1]).job.stats().pentatopes(), 12u);
}

// The cores go to the running jobs (core_allocator.h): a lone job gets all of them, a second
// one half, and the first gets them back when the second ends; threads asked for are kept.
TEST_F(JobManagerTest, SharesTheCoresAmongTheRunningJobs) {
  ManagerConfig config;
  config.running_jobs = 4;
  config.threads_per_job = 16;
  config.cores = 16;
  JobManager jobs(store_, config, nullptr, fake_.runner());
  jobs.start();
  jobs.submit(upload(21).spec, upload(21).data);
  ASSERT_TRUE(fake_.wait_started(1));
  EXPECT_EQ(fake_.threads(21), 16u);
  EXPECT_EQ(fake_.limit(21), 16u);
  const std::string second = jobs.submit(upload(22).spec, upload(22).data).job.id();
  ASSERT_TRUE(fake_.wait_started(2));
  EXPECT_EQ(fake_.threads(22), 8u);
  EXPECT_EQ(fake_.limit(21), 8u);
  fake_.release(22);
  EXPECT_EQ(wait_for_state(jobs, second, v1::JOB_STATE_SUCCEEDED).state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(fake_.limit(21), 16u);
  Upload asked = upload(23);
  asked.spec.mutable_params()->set_threads(3);
  jobs.submit(asked.spec, asked.data);
  ASSERT_TRUE(fake_.wait_started(3));
  EXPECT_EQ(fake_.threads(23), 3u);
  EXPECT_EQ(fake_.limit(21), 13u);  // 16 cores over 2 jobs, less than job 23 can use
  fake_.release();
}

TEST_F(JobManagerTest, AWatcherSeesEveryStepUntilTheJobEnds) {
  JobManager jobs(store_, {}, nullptr, fake_.runner());
  jobs.start();
  const std::string id = jobs.submit(upload(21).spec, upload(21).data).job.id();
  // The job is released only once the watch has its first event: a watch that begins after the
  // job ended sees one snapshot, not the steps.
  std::promise<void> watching;
  auto watched = std::async(std::launch::async, [&] {
    std::vector<v1::JobEvent> events;
    const auto end = jobs.watch(
        id, 0,
        [&](const v1::JobEvent& e) {
          if (events.empty()) watching.set_value();
          return events.push_back(e), true;
        },
        [] { return false; });
    return std::pair{end, events};
  });
  ASSERT_TRUE(fake_.wait_started(1));
  ASSERT_EQ(watching.get_future().wait_for(std::chrono::seconds(10)), std::future_status::ready);
  fake_.release();
  ASSERT_EQ(watched.wait_for(std::chrono::seconds(10)), std::future_status::ready);
  const auto [end, events] = watched.get();
  EXPECT_EQ(end, JobManager::WatchEnd::job_ended);
  ASSERT_GE(events.size(), 3u);
  EXPECT_TRUE(events.front().has_snapshot()) << "the whole job first";
  bool progress = false;
  for (std::size_t i = 1; i < events.size(); ++i) {
    EXPECT_GT(events[i].sequence(), events[i - 1].sequence());
    progress |= events[i].has_progress() && events[i].progress().vertices() == 21;
  }
  // The report may come before the watch starts: then the first snapshot holds it.
  progress |= events.front().snapshot().progress().vertices() == 21;
  EXPECT_TRUE(progress) << "the runner's progress report";
  EXPECT_EQ(events.back().event_case(), v1::JobEvent::kState);
  EXPECT_EQ(events.back().state(), v1::JOB_STATE_SUCCEEDED);

  // A watcher that comes back after the last event it saw gets nothing more: the job ended.
  int more = 0;
  EXPECT_EQ(jobs.watch(
                id, events.back().sequence(), [&](const v1::JobEvent&) { return ++more, true; },
                [] { return false; }),
            JobManager::WatchEnd::job_ended);
  EXPECT_EQ(more, 0);
  EXPECT_EQ(refusal([&] {
              jobs.watch(
                  "no-such-job", 0, [](const v1::JobEvent&) { return true; }, [] { return false; });
            }),
            wire::ErrorCode::not_found);
}

TEST_F(JobManagerTest, AWatchEndsWhenItsJobIsDeletedOrItsWatcherLeaves) {
  JobManager jobs(store_, {}, nullptr, fake_.runner());
  jobs.start();
  const std::string running = jobs.submit(upload(31).spec, upload(31).data).job.id();
  const std::string queued = jobs.submit(upload(32).spec, upload(32).data).job.id();
  ASSERT_TRUE(fake_.wait_started(1));
  auto watched = std::async(std::launch::async, [&] {
    return jobs.watch(
        queued, 0, [](const v1::JobEvent&) { return true; }, [] { return false; });
  });
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  jobs.remove(queued);
  ASSERT_EQ(watched.wait_for(std::chrono::seconds(10)), std::future_status::ready);
  EXPECT_EQ(watched.get(), JobManager::WatchEnd::job_deleted);
  EXPECT_EQ(jobs.watch(
                running, 0, [](const v1::JobEvent&) { return false; }, [] { return false; }),
            JobManager::WatchEnd::watcher_left);
  EXPECT_EQ(jobs.watch(
                running, 0, [](const v1::JobEvent&) { return true; }, [] { return true; }),
            JobManager::WatchEnd::watcher_left);
  EXPECT_EQ(refusal([&] { jobs.remove(running); }), wire::ErrorCode::failed_precondition);
  fake_.release();
}

TEST_F(JobManagerTest, CancelsQueuedAndRunningJobsAndReportsAFailedOne) {
  JobManager jobs(store_, {}, nullptr, fake_.runner());
  jobs.start();
  const std::string running = jobs.submit(upload(41).spec, upload(41).data).job.id();
  const std::string queued = jobs.submit(upload(42).spec, upload(42).data).job.id();
  const std::string failing =
      jobs.submit(upload(FakeRunner::kFailingSeed).spec, upload(FakeRunner::kFailingSeed).data)
          .job.id();
  ASSERT_TRUE(fake_.wait_started(1));
  EXPECT_EQ(jobs.cancel(queued).state(), v1::JOB_STATE_CANCELLED);
  jobs.cancel(running);
  EXPECT_EQ(wait_for_state(jobs, running, v1::JOB_STATE_CANCELLED).state(),
            v1::JOB_STATE_CANCELLED);
  fake_.release();
  const v1::Job failed = wait_for_state(jobs, failing, v1::JOB_STATE_FAILED);
  EXPECT_EQ(failed.state(), v1::JOB_STATE_FAILED);
  EXPECT_EQ(failed.error(), "planted failure");
  EXPECT_EQ(fake_.started(), (std::vector<std::uint64_t>{41, FakeRunner::kFailingSeed}))
      << "the cancelled queued job never ran";
  EXPECT_EQ(refusal([&] { jobs.result(failing); }), wire::ErrorCode::failed_precondition);
  EXPECT_EQ(refusal([&] { jobs.result(running); }), wire::ErrorCode::cancelled);
}

TEST_F(JobManagerTest, RefusesPastTheQueueLimitAndDeduplicatesRequestIds) {
  ManagerConfig config;
  config.max_queued_jobs = 1;
  JobManager jobs(store_, config, nullptr, fake_.runner());
  jobs.start();
  const auto first = jobs.submit(upload(51, "request-a").spec, upload(51).data);
  ASSERT_TRUE(fake_.wait_started(1));
  jobs.submit(upload(52).spec, upload(52).data);
  EXPECT_EQ(refusal([&] { jobs.submit(upload(53).spec, upload(53).data); }),
            wire::ErrorCode::resource_exhausted);
  const auto again = jobs.submit(upload(51, "request-a").spec, upload(51).data);
  EXPECT_TRUE(again.deduplicated);
  EXPECT_EQ(again.job.id(), first.job.id());
  const Upload other = upload(54, "request-a", 4);
  EXPECT_EQ(refusal([&] { jobs.submit(other.spec, other.data); }), wire::ErrorCode::already_exists)
      << "one request id, two images";
  Upload corrupt = upload(55);
  corrupt.data[3] ^= 1;
  EXPECT_EQ(refusal([&] { jobs.submit(corrupt.spec, corrupt.data); }),
            wire::ErrorCode::invalid_argument);
  fake_.release();
}

TEST_F(JobManagerTest, ARestartedManagerRunsWhatWasQueuedOrRunning) {
  std::string running, queued;
  {
    JobManager jobs(store_, {}, nullptr, fake_.runner());
    jobs.start();
    running = jobs.submit(upload(61).spec, upload(61).data).job.id();
    queued = jobs.submit(upload(62).spec, upload(62).data).job.id();
    ASSERT_TRUE(fake_.wait_started(1));
  }  // stopped with job 61 running: it stays RUNNING on disk
  FakeRunner after;
  after.release();
  JobManager jobs(store_, {}, nullptr, after.runner());
  EXPECT_TRUE(jobs.start().empty());
  for (const auto& id : {running, queued})
    EXPECT_EQ(wait_for_state(jobs, id, v1::JOB_STATE_SUCCEEDED).state(), v1::JOB_STATE_SUCCEEDED)
        << id;
  EXPECT_EQ(jobs.result(queued).mesh, "mesh 62");
}

}  // namespace
}  // namespace mesh4d::server
