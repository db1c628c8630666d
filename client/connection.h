// Options shared by every subcommand, and the channel they open to the server.
#pragma once

#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

namespace CLI {
class App;
}

namespace mesh4d::client {

struct GlobalOptions {
  std::string server = "127.0.0.1:50051";
  double timeout_seconds = 10.0;  // per call that is not a stream
  std::string token;              // sent as "authorization: Bearer <token>" when set
  std::string tls_ca;             // PEM roots: when set, the channel uses TLS
};

/// Registers --server (MESH4D_SERVER), --token (MESH4D_TOKEN), --tls-ca (MESH4D_TLS_CA) and
/// --timeout on the top-level app.
void add_global_options(CLI::App& app, GlobalOptions& options);

std::shared_ptr<grpc::Channel> open_channel(const GlobalOptions& options);

/// A deadline `options.timeout_seconds` from now.
std::chrono::system_clock::time_point call_deadline(const GlobalOptions& options);

/// Sets the token on a call's context (and the deadline when `deadline` is true).
void prepare(grpc::ClientContext& context, const GlobalOptions& options, bool deadline = true);

/// Maps a failed call to the exit code for its kind and prints one clear line to stderr.
int report_rpc_error(const std::string& what, const grpc::Status& status,
                     const GlobalOptions& options);

}  // namespace mesh4d::client
