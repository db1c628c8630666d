#include "server_fixture.h"

#include <gtest/gtest.h>

#include <sstream>
#include <thread>

#include "wire/grpc_library.h"
#include "wire/submit_stream.h"
#include "wire/upload_codec.h"

namespace mesh4d::testing {
namespace {

// The tests' clients hold gRPC from the first test to the last and let it go in the
// environment's TearDown, on the main thread, before main returns (wire/grpc_library.h).
class GrpcLibraryEnvironment : public ::testing::Environment {
 public:
  void SetUp() override { library_ = std::make_unique<wire::GrpcLibrary>(); }
  void TearDown() override { library_.reset(); }

 private:
  std::unique_ptr<wire::GrpcLibrary> library_;
};

[[maybe_unused]] const auto* const kGrpcLibrary =
    ::testing::AddGlobalTestEnvironment(new GrpcLibraryEnvironment);

}  // namespace

RunningServer::RunningServer(const std::string& data_dir, const std::vector<std::string>& flags) {
  const std::string port_file = data_dir + ".port";
  std::remove(port_file.c_str());
  std::vector<std::string> argv{
      MESH4D_SERVER_BIN, "--listen",      "127.0.0.1:0",       "--port-file", port_file,
      "--data-dir",      data_dir,        "--threads-per-job", "1",           "--metrics-listen",
      "127.0.0.1:0",     "--http-listen", "127.0.0.1:0"};
  argv.insert(argv.end(), flags.begin(), flags.end());
  process_ = std::make_unique<ChildProcess>(argv, data_dir + ".log");
  const std::string port = wait_for_file(port_file, std::chrono::seconds(20));
  if (port.empty()) return;
  address_ = "127.0.0.1:" + std::to_string(std::stoi(port));
  // Lines: gRPC port, metrics port, HTTP port (0: not served).
  std::istringstream lines(port);
  int grpc_port = 0;
  lines >> grpc_port >> metrics_port_ >> http_port_;
}

std::unique_ptr<v1::MeshService::Stub> RunningServer::stub() const {
  return v1::MeshService::NewStub(
      grpc::CreateChannel(address_, grpc::InsecureChannelCredentials()));
}

Upload make_upload(const domain::LabelImage4& image, double delta, const std::string& request_id) {
  Upload u;
  u.data = wire::encode_upload(image, u.spec.mutable_image());
  u.spec.mutable_params()->set_delta(delta);
  u.spec.set_request_id(request_id);
  return u;
}

grpc::Status submit(v1::MeshService::Stub& stub, const v1::JobSpec& spec, const std::string& data,
                    v1::SubmitJobResponse* response, const std::string& token) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  if (!token.empty()) context.AddMetadata("authorization", "Bearer " + token);
  // Small chunks: a test's upload crosses many messages.
  return wire::submit_job(stub, context, spec, data, response, 1 << 16);
}

v1::Job wait_until_done(v1::MeshService::Stub& stub, const std::string& id,
                        std::chrono::seconds timeout) {
  const auto end = std::chrono::steady_clock::now() + timeout;
  v1::Job job;
  while (std::chrono::steady_clock::now() < end) {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(id);
    if (stub.GetJob(&context, request, &job).ok() && job.state() != v1::JOB_STATE_QUEUED &&
        job.state() != v1::JOB_STATE_RUNNING)
      return job;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return job;
}

}  // namespace mesh4d::testing
