// Configuration of mesh4d-server. Embedded defaults that just work (loopback, data in
// ./mesh4d-data); a JSON file (--config) overrides them, MESH4D_* environment variables override
// the file, and flags override everything. `mesh4d-server --help` lists them all.
#pragma once

#include <cstdint>
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
  std::string data_dir = "mesh4d-data";  // jobs, inputs and results
  unsigned running_jobs = 0;             // jobs refined at once; 0: one per core
  unsigned threads_per_job = 0;          // 0: every core
  unsigned max_queued_jobs = 16;
  std::uint64_t max_image_mb = 2048;
  std::uint64_t max_vertex_budget = 20'000'000;
  double retention_hours = 0;  // finished jobs deleted after this; 0: kept until deleted
  std::string token;           // when set, calls need "authorization: Bearer <token>"
  std::string tls_cert;        // PEM files: both set switches the API to TLS
  std::string tls_key;
  std::string metrics_listen = "127.0.0.1:9464";  // Prometheus /metrics; empty: off
  std::string http_listen = "127.0.0.1:8080";     // REST API and dashboard; empty: off
  std::string log_format = "json";                // "json": one object a line; "text"
};

/// Loads a JSON configuration file (keys as the flags without dashes, '-' as '_'). Throws
/// std::runtime_error naming the file and key on a bad file.
void load_config_file(const std::string& path, ServerOptions& options);

/// Registers the options on `app`, each also readable from a MESH4D_* environment variable.
/// Call after load_config_file: the loaded values become the defaults flags override.
void add_server_options(CLI::App& app, ServerOptions& options);

}  // namespace mesh4d::server
