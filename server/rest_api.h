// The HTTP/1.1 JSON face of the job service, on its own port, over the same JobManager as the
// gRPC service (no job logic here): routes, the token, JSON bodies, Server-Sent Events, the
// mesh download, time slices as .vtu, and the dashboard page. docs/openapi.yaml describes it.
//
// Served by civetweb, which the server already carries for prometheus-cpp's /metrics: a small,
// long-maintained C library in Debian, with its own worker threads (one per open request, so a
// long event stream never blocks other calls).
#pragma once

#include <memory>
#include <string>

#include "job_manager.h"

class CivetServer;

namespace mesh4d::server {

class RestApi {
 public:
  /// Listens on `listen` (host:port, port 0: any free one). Throws std::runtime_error when it
  /// cannot. `token`: when not empty, every /v1 call needs "Authorization: Bearer <token>" (or
  /// ?access_token=, for browsers' EventSource).
  RestApi(JobManager& jobs, const std::string& listen, std::string token,
          std::uint64_t max_body_bytes, JobObserver* observer = nullptr);
  ~RestApi();
  int port() const;

 private:
  class Handler;
  std::unique_ptr<Handler> handler_;
  std::unique_ptr<CivetServer> server_;
};

}  // namespace mesh4d::server
