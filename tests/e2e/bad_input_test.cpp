// Every bad request of the job service gets its status and a message that says what is wrong;
// the server stays healthy and keeps its jobs. Also the token and the client's failure paths.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "domain/phantoms.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

struct BadUpload {
  const char* name;
  std::function<void(Upload&)> spoil;
  grpc::StatusCode code;
  const char* message;  // a part of the expected message
};

TEST(BadInput, EachBadUploadGetsItsStatusAndTheServerStaysHealthy) {
  const std::string dir = make_temp_dir("mesh4d-bad");
  RunningServer server(dir + "/data", {"--max-vertex-budget", "100000", "--max-image-mb", "8"});
  ASSERT_FALSE(server.address().empty());
  auto stub = server.stub();
  const auto image = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
  const Upload good = make_upload(image, 3, "");
  v1::SubmitJobResponse kept;
  const grpc::Status good_status = submit(*stub, good.spec, good.data, &kept);
  ASSERT_TRUE(good_status.ok()) << good_status.error_message();

  const BadUpload cases[] = {
      {"zero dims", [](Upload& u) { u.spec.mutable_image()->mutable_dims()->set_z(0); },
       grpc::StatusCode::INVALID_ARGUMENT, "dims"},
      {"NaN spacing",
       [](Upload& u) { u.spec.mutable_image()->mutable_spacing()->set_y(std::nan("")); },
       grpc::StatusCode::INVALID_ARGUMENT, "spacing.y"},
      {"negative spacing", [](Upload& u) { u.spec.mutable_image()->mutable_spacing()->set_t(-1); },
       grpc::StatusCode::INVALID_ARGUMENT, "spacing.t"},
      {"unknown label type",
       [](Upload& u) { u.spec.mutable_image()->set_label_type(v1::LABEL_TYPE_UNSPECIFIED); },
       grpc::StatusCode::INVALID_ARGUMENT, "label_type"},
      {"byte size off", [](Upload& u) { u.spec.mutable_image()->set_byte_size(12); },
       grpc::StatusCode::INVALID_ARGUMENT, "byte_size"},
      {"truncated data", [](Upload& u) { u.data.resize(u.data.size() / 2); },
       grpc::StatusCode::INVALID_ARGUMENT, "received"},
      {"too much data", [](Upload& u) { u.data += "xx"; }, grpc::StatusCode::INVALID_ARGUMENT,
       "more label data"},
      {"checksum mismatch", [](Upload& u) { u.data[7] ^= 1; }, grpc::StatusCode::INVALID_ARGUMENT,
       "sha256"},
      {"no checksum", [](Upload& u) { u.spec.mutable_image()->clear_sha256(); },
       grpc::StatusCode::INVALID_ARGUMENT, "sha256"},
      {"no spec image", [](Upload& u) { u.spec.clear_image(); }, grpc::StatusCode::INVALID_ARGUMENT,
       "image"},
      {"empty labels",
       [&](Upload& u) {
         domain::LabelImage4 empty(image.dims(), image.spacing());
         u = make_upload(empty, 3, "");
       },
       grpc::StatusCode::INVALID_ARGUMENT, "foreground"},
      {"negative delta", [](Upload& u) { u.spec.mutable_params()->set_delta(-2); },
       grpc::StatusCode::INVALID_ARGUMENT, "delta"},
      {"absurd radius-edge bound",
       [](Upload& u) { u.spec.mutable_params()->set_radius_edge_bound(0.1); },
       grpc::StatusCode::INVALID_ARGUMENT, "radius_edge_bound"},
      {"time extension over 64 frames",
       [](Upload& u) { u.spec.mutable_params()->set_extend_time_frames(65); },
       grpc::StatusCode::INVALID_ARGUMENT, "extend_time_frames"},
      {"vertex budget over the limit",
       [](Upload& u) { u.spec.mutable_params()->set_vertex_budget(1'000'000); },
       grpc::StatusCode::RESOURCE_EXHAUSTED, "vertex_budget"},
      {"image over the limit",
       [](Upload& u) {
         auto* h = u.spec.mutable_image();
         h->mutable_dims()->set_x(4096);
         h->set_byte_size(4096ull * 16 * 16 * 16);
       },
       grpc::StatusCode::RESOURCE_EXHAUSTED, "at most"},
      {"request id reused for another image",
       [&](Upload& u) {
         u = make_upload(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 6), 3,
                         "first");
       },
       grpc::StatusCode::ALREADY_EXISTS, "already used"},
      {"request id reused with other parameters",
       [&](Upload& u) {
         u.spec.set_request_id("first");
         u.spec.mutable_params()->set_delta(4);
       },
       grpc::StatusCode::ALREADY_EXISTS, "different parameters"},
      {"rule order the server does not know",
       [&](Upload& u) { u.spec.mutable_params()->set_rule_order(static_cast<v1::RuleOrder>(99)); },
       grpc::StatusCode::INVALID_ARGUMENT, "rule_order 99"},
  };
  // The reused request id needs a first job under that id.
  const Upload first = make_upload(image, 3, "first");
  v1::SubmitJobResponse first_response;
  ASSERT_TRUE(submit(*stub, first.spec, first.data, &first_response).ok());

  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    Upload u = make_upload(image, 3, "");
    c.spoil(u);
    v1::SubmitJobResponse response;
    const grpc::Status s = submit(*stub, u.spec, u.data, &response);
    EXPECT_EQ(s.error_code(), c.code) << s.error_message();
    EXPECT_NE(s.error_message().find(c.message), std::string::npos) << s.error_message();
  }

  // Unknown ids, an unfinished job's result, a bad page token.
  auto expect_code = [](const grpc::Status& s, grpc::StatusCode code) {
    EXPECT_EQ(s.error_code(), code) << s.error_message();
    EXPECT_FALSE(s.error_message().empty());
  };
  {
    grpc::ClientContext c;
    v1::GetJobRequest r;
    r.set_job_id("no-such-job");
    v1::Job j;
    expect_code(stub->GetJob(&c, r, &j), grpc::StatusCode::NOT_FOUND);
  }
  {
    grpc::ClientContext c;
    v1::CancelJobRequest r;
    r.set_job_id("no-such-job");
    v1::Job j;
    expect_code(stub->CancelJob(&c, r, &j), grpc::StatusCode::NOT_FOUND);
  }
  {
    grpc::ClientContext c;
    v1::DeleteJobRequest r;
    r.set_job_id("no-such-job");
    v1::DeleteJobResponse d;
    expect_code(stub->DeleteJob(&c, r, &d), grpc::StatusCode::NOT_FOUND);
  }
  {
    grpc::ClientContext c;
    v1::WatchJobRequest r;
    r.set_job_id("no-such-job");
    auto reader = stub->WatchJob(&c, r);
    v1::JobEvent e;
    EXPECT_FALSE(reader->Read(&e));
    expect_code(reader->Finish(), grpc::StatusCode::NOT_FOUND);
  }
  {
    // A job cancelled while queued or running has no result.
    const Upload slow = make_upload(domain::hypersphere_phantom(), 1.5, "slow");
    v1::SubmitJobResponse s;
    ASSERT_TRUE(submit(*stub, slow.spec, slow.data, &s).ok());
    grpc::ClientContext c;
    v1::GetResultRequest r;
    r.set_job_id(s.job().id());
    auto reader = stub->GetResult(&c, r);
    v1::GetResultResponse m;
    EXPECT_FALSE(reader->Read(&m));
    expect_code(reader->Finish(), grpc::StatusCode::FAILED_PRECONDITION);
    grpc::ClientContext cc;
    v1::CancelJobRequest cancel;
    cancel.set_job_id(s.job().id());
    v1::Job j;
    ASSERT_TRUE(stub->CancelJob(&cc, cancel, &j).ok());
    EXPECT_EQ(wait_until_done(*stub, s.job().id()).state(), v1::JOB_STATE_CANCELLED);
    // A cancelled job has no result: CANCELLED, saying so.
    grpc::ClientContext c2;
    auto reader2 = stub->GetResult(&c2, r);
    EXPECT_FALSE(reader2->Read(&m));
    const grpc::Status after = reader2->Finish();
    expect_code(after, grpc::StatusCode::CANCELLED);
    EXPECT_NE(after.error_message().find("was cancelled"), std::string::npos)
        << after.error_message();
  }
  {
    grpc::ClientContext c;
    v1::ListJobsRequest r;
    r.set_page_token("garbage");
    v1::ListJobsResponse l;
    expect_code(stub->ListJobs(&c, r, &l), grpc::StatusCode::INVALID_ARGUMENT);
  }
  // Still serving, and the good job finished.
  const RunResult health = run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "health"});
  EXPECT_EQ(health.exit_code, 0) << health.output;
  EXPECT_EQ(wait_until_done(*stub, kept.job().id()).state(), v1::JOB_STATE_SUCCEEDED);
}

TEST(BadInput, TokenIsRequiredWhenConfigured) {
  const std::string dir = make_temp_dir("mesh4d-token");
  RunningServer server(dir + "/data", {"--token", "s3cret"});
  auto stub = server.stub();
  const Upload u =
      make_upload(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5), 3, "tok");
  v1::SubmitJobResponse r;
  EXPECT_EQ(submit(*stub, u.spec, u.data, &r).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  EXPECT_EQ(submit(*stub, u.spec, u.data, &r, "wrong").error_code(),
            grpc::StatusCode::PERMISSION_DENIED);
  EXPECT_TRUE(submit(*stub, u.spec, u.data, &r, "s3cret").ok());
  const RunResult without = run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "list"});
  EXPECT_EQ(without.exit_code, 4) << without.output;
  const RunResult with =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "--token", "s3cret", "list"});
  EXPECT_EQ(with.exit_code, 0) << with.output;
  EXPECT_NE(with.output.find(r.job().id()), std::string::npos) << with.output;
}

TEST(ClientFailures, EachSubcommandFailsWithItsExitCode) {
  const std::string dir = make_temp_dir("mesh4d-client");
  RunningServer server(dir + "/data");
  const std::string a = server.address();
  struct Case {
    std::vector<std::string> args;
    int code;
    const char* message;
  };
  const Case cases[] = {
      {{"status", "nope"}, 4, "no job with id 'nope'"},
      {{"watch", "nope"}, 4, "no job"},
      {{"cancel", "nope"}, 4, "no job"},
      {{"delete", "nope"}, 4, "no job"},
      {{"fetch", "nope", "--out", dir + "/x.m4d"}, 4, "no job"},
      {{"list", "--state", "sleeping"}, 2, "unknown state"},
      {{"submit", dir + "/missing.nii.gz"}, 2, "missing.nii.gz"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> argv{MESH4D_CLIENT_BIN, "--server", a};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const RunResult r = run_command(argv);
    SCOPED_TRACE(c.args.front());
    EXPECT_EQ(r.exit_code, c.code) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
  }
  // An unreadable image: a file that is not an image at all.
  {
    std::FILE* f = std::fopen((dir + "/junk.nii").c_str(), "w");
    std::fputs("not an image", f);
    std::fclose(f);
    const RunResult r =
        run_command({MESH4D_CLIENT_BIN, "--server", a, "submit", dir + "/junk.nii"});
    EXPECT_EQ(r.exit_code, 6) << r.output;
  }
  // No server: every call says so with exit code 3.
  ASSERT_EQ(server.process().stop(SIGTERM), 0);
  const RunResult r = run_command({MESH4D_CLIENT_BIN, "--server", a, "--timeout", "2", "list"});
  EXPECT_EQ(r.exit_code, 3) << r.output;
}

}  // namespace
}  // namespace mesh4d::testing
