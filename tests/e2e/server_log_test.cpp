// The server's log is structured: one JSON object per line, and the lines about a job carry its
// id as a field, so a log shipper can follow one job.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <string>

#include "domain/phantoms.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

std::vector<nlohmann::json> read_json_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<nlohmann::json> lines;
  std::string line;
  while (std::getline(in, line)) {
    nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
    EXPECT_TRUE(j.is_object()) << "not a JSON object: " << line;
    if (j.is_object()) lines.push_back(std::move(j));
  }
  return lines;
}

TEST(ServerLog, OneJsonObjectPerLineWithTheJobId) {
  const std::string dir = make_temp_dir("mesh4d-log");
  std::string id;
  double time_scale = 0;
  {
    RunningServer server(dir + "/data");
    ASSERT_FALSE(server.address().empty());
    auto stub = server.stub();
    const auto image = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
    const Upload u = make_upload(image, 3, "log-1");
    v1::SubmitJobResponse response;
    ASSERT_TRUE(submit(*stub, u.spec, u.data, &response).ok());
    id = response.job().id();
    const v1::Job done = wait_until_done(*stub, id);
    EXPECT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED);
    time_scale = done.params().time_scale();
    EXPECT_EQ(server.process().stop(SIGTERM), 0);
  }
  const auto lines = read_json_lines(dir + "/data.log");
  ASSERT_GE(lines.size(), 4u);
  std::vector<std::string> about_job;
  for (const auto& j : lines) {
    EXPECT_TRUE(j.contains("time") && j["time"].is_string()) << j.dump();
    EXPECT_TRUE(j.contains("level") && j["level"].is_string()) << j.dump();
    EXPECT_TRUE(j.contains("msg") && j["msg"].is_string()) << j.dump();
    if (j.value("job", "") == id) about_job.push_back(j["msg"]);
  }
  // Queued, running, succeeded: each a line of its own, with the id as a field.
  ASSERT_EQ(about_job.size(), 3u) << ::testing::PrintToString(about_job);
  EXPECT_EQ(about_job[0].rfind("queued", 0), 0u) << about_job[0];
  // The time scale the job used, chosen from the data (no time scale was asked for).
  EXPECT_GT(time_scale, 0);
  const std::string running = "running: delta 3, time scale ";
  ASSERT_EQ(about_job[1].rfind(running, 0), 0u) << about_job[1];
  EXPECT_DOUBLE_EQ(std::stod(about_job[1].substr(running.size())), time_scale) << about_job[1];
  EXPECT_NE(about_job[1].find(" per frame"), std::string::npos) << about_job[1];
  EXPECT_EQ(about_job[2].rfind("succeeded", 0), 0u) << about_job[2];
  EXPECT_EQ(about_job[2].find(id), std::string::npos) << "the id belongs in the field";
}

}  // namespace
}  // namespace mesh4d::testing
