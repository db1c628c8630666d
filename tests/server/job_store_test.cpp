// The durable store: what it keeps comes back after a restart, a job half-written by a crash is
// cleaned away, and an unreadable record is reported and skipped, not fatal.
#include "job_store.h"

#include <gtest/gtest.h>

#include <fstream>

#include "../e2e/process.h"

namespace mesh4d::server {
namespace {

v1::Job job(const std::string& id, v1::JobState state) {
  v1::Job j;
  j.set_id(id);
  j.set_state(state);
  j.set_name("job " + id);
  return j;
}

TEST(JobStore, KeepsRecordsInputsAndResultsAcrossARestart) {
  const std::string dir = mesh4d::testing::make_temp_dir("mesh4d-store");
  {
    JobStore store(dir);
    store.create(job("a", v1::JOB_STATE_QUEUED), "input a");
    store.create(job("b", v1::JOB_STATE_QUEUED), "input b");
    v1::Job done = job("b", v1::JOB_STATE_SUCCEEDED);
    store.save(done);
    store.save_result("b", "result b");
  }
  JobStore store(dir);
  std::vector<std::string> problems;
  auto jobs = store.load_all(&problems);
  EXPECT_TRUE(problems.empty());
  ASSERT_EQ(jobs.size(), 2u);
  std::sort(jobs.begin(), jobs.end(),
            [](const v1::Job& x, const v1::Job& y) { return x.id() < y.id(); });
  EXPECT_EQ(jobs[0].state(), v1::JOB_STATE_QUEUED);
  EXPECT_EQ(jobs[1].state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(jobs[1].name(), "job b");
  EXPECT_EQ(store.read_input("a"), "input a");
  EXPECT_EQ(store.read_result("b"), "result b");
  store.remove("a");
  EXPECT_EQ(store.load_all(nullptr).size(), 1u);
  EXPECT_THROW(store.read_input("a"), std::system_error);
}

TEST(JobStore, CleansHalfWrittenJobsAndReportsUnreadableRecords) {
  const std::string dir = mesh4d::testing::make_temp_dir("mesh4d-store");
  JobStore store(dir);
  store.create(job("good", v1::JOB_STATE_QUEUED), "input");
  // A crash before job.pb: the input alone.
  std::filesystem::create_directories(store.root() / "jobs" / "half");
  std::ofstream(store.root() / "jobs" / "half" / "input.bin") << "input";
  // A record that is not a Job, and one whose id is not its folder's.
  std::filesystem::create_directories(store.root() / "jobs" / "garbage");
  std::ofstream(store.root() / "jobs" / "garbage" / "job.pb") << "\xff\xff\xff not a protobuf";
  std::filesystem::create_directories(store.root() / "jobs" / "moved");
  std::ofstream(store.root() / "jobs" / "moved" / "job.pb")
      << job("elsewhere", v1::JOB_STATE_QUEUED).SerializeAsString();
  std::vector<std::string> problems;
  const auto jobs = store.load_all(&problems);
  ASSERT_EQ(jobs.size(), 1u);
  EXPECT_EQ(jobs[0].id(), "good");
  EXPECT_FALSE(std::filesystem::exists(store.root() / "jobs" / "half"));
  ASSERT_EQ(problems.size(), 2u);
  for (const auto& p : problems) EXPECT_NE(p.find("unreadable job record"), std::string::npos);
}

}  // namespace
}  // namespace mesh4d::server
