#include "connection.h"

#include <CLI/CLI.hpp>
#include <fstream>
#include <iostream>

#include "exit_codes.h"

namespace mesh4d::client {

void add_global_options(CLI::App& app, GlobalOptions& options) {
  app.add_option("--server", options.server, "server address host:port")
      ->envname("MESH4D_SERVER")
      ->capture_default_str();
  app.add_option("--token", options.token, "access token of the server")->envname("MESH4D_TOKEN");
  app.add_option("--tls-ca", options.tls_ca, "PEM root certificates: connect with TLS")
      ->envname("MESH4D_TLS_CA");
  app.add_option("--timeout", options.timeout_seconds, "seconds to wait for each call")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

std::shared_ptr<grpc::Channel> open_channel(const GlobalOptions& options) {
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(64 << 20);
  if (options.tls_ca.empty())
    return grpc::CreateCustomChannel(options.server, grpc::InsecureChannelCredentials(), args);
  std::ifstream in(options.tls_ca);
  grpc::SslCredentialsOptions ssl;
  ssl.pem_root_certs.assign(std::istreambuf_iterator<char>(in), {});
  return grpc::CreateCustomChannel(options.server, grpc::SslCredentials(ssl), args);
}

void prepare(grpc::ClientContext& context, const GlobalOptions& options, bool deadline) {
  if (!options.token.empty()) context.AddMetadata("authorization", "Bearer " + options.token);
  if (deadline) context.set_deadline(call_deadline(options));
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
