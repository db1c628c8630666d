// Command-line and environment options of mesh4d-server.
#pragma once

#include <string>

namespace CLI {
class App;
}

namespace mesh4d::server {

struct ServerOptions {
  /// host:port for the gRPC API. Loopback by default: exposing the service is a deliberate act.
  /// Port 0 picks a free port (tests use it with port_file).
  std::string listen = "127.0.0.1:50051";
  /// When set, the bound port is written here (atomically) once the server accepts calls.
  std::string port_file;
};

/// Registers the options on `app`, each also readable from a MESH4D_* environment variable.
void add_server_options(CLI::App& app, ServerOptions& options);

}  // namespace mesh4d::server
