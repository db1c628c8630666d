#include "connection.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "exit_codes.h"

namespace mesh4d::client {

void add_global_options(CLI::App& app, GlobalOptions& options) {
  app.add_option("--server", options.server, "server address host:port")
      ->envname("MESH4D_SERVER")
      ->capture_default_str();
  app.add_option("--timeout", options.timeout_seconds, "seconds to wait for each call")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

std::shared_ptr<grpc::Channel> open_channel(const GlobalOptions& options) {
  return grpc::CreateChannel(options.server, grpc::InsecureChannelCredentials());
}

std::chrono::system_clock::time_point call_deadline(const GlobalOptions& options) {
  return std::chrono::system_clock::now() +
         std::chrono::duration_cast<std::chrono::system_clock::duration>(
             std::chrono::duration<double>(options.timeout_seconds));
}

int report_rpc_error(const std::string& what, const grpc::Status& status,
                     const GlobalOptions& options) {
  const bool unreachable = status.error_code() == grpc::StatusCode::UNAVAILABLE ||
                           status.error_code() == grpc::StatusCode::DEADLINE_EXCEEDED;
  if (unreachable) {
    std::cerr << "mesh4d-client: " << what << ": no answer from server " << options.server << " ("
              << status.error_message() << ")\n";
    return kExitUnavailable;
  }
  std::cerr << "mesh4d-client: " << what << ": " << status.error_message() << " (status "
            << status.error_code() << ")\n";
  return kExitServerError;
}

}  // namespace mesh4d::client
