// A real mesh4d-server on a loopback port for end-to-end tests, with a gRPC stub to it and
// helpers that build uploads from engine images.
#pragma once

#include <grpcpp/grpcpp.h>
#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

#include "domain/label_image.h"
#include "mesh4d/v1/mesh4d.grpc.pb.h"
#include "process.h"

namespace mesh4d::testing {

class RunningServer {
 public:
  /// Starts mesh4d-server on 127.0.0.1:0 with `data_dir` and the extra flags; waits for its port.
  RunningServer(const std::string& data_dir, const std::vector<std::string>& flags = {});
  const std::string& address() const { return address_; }
  int metrics_port() const { return metrics_port_; }
  int http_port() const { return http_port_; }
  ChildProcess& process() { return *process_; }
  std::unique_ptr<v1::MeshService::Stub> stub() const;

 private:
  std::string address_;
  int metrics_port_ = 0;
  int http_port_ = 0;
  std::unique_ptr<ChildProcess> process_;
};

/// The raw upload of an image (uint8 labels) and its header.
struct Upload {
  v1::JobSpec spec;
  std::string data;
};
Upload make_upload(const domain::LabelImage4& image, double delta, const std::string& request_id);

/// Sends spec then data in 64 KiB chunks.
grpc::Status submit(v1::MeshService::Stub& stub, const v1::JobSpec& spec, const std::string& data,
                    v1::SubmitJobResponse* response, const std::string& token = "");

/// Waits (polling GetJob) until the job leaves QUEUED/RUNNING or `timeout` passes.
v1::Job wait_until_done(v1::MeshService::Stub& stub, const std::string& id,
                        std::chrono::seconds timeout = std::chrono::seconds(120));

}  // namespace mesh4d::testing
