// mesh4d-server: the meshing service (mesh4d.v1.MeshService over a durable job queue), gRPC
// health and reflection; runs until SIGINT or SIGTERM. Jobs running at shutdown stay RUNNING on
// disk and run again at the next start.
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <malloc.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>

#include "civetweb_tls.h"
#include "job_log.h"
#include "job_manager.h"
#include "job_store.h"
#include "listener_waker.h"
#include "mesh_service.h"
#include "metrics.h"
#include "rest_api.h"
#include "server_options.h"
#include "wire/grpc_library.h"

namespace {

// "host:0" → "host:PORT", for the log line.
std::string bound_address(const std::string& listen, int port) {
  const auto colon = listen.rfind(':');
  return listen.substr(0, colon) + ":" + std::to_string(port);
}

// Written to a temporary file then renamed, so a reader never sees a partial number.
// The gRPC port on the first line, then the metrics port and the HTTP port (0 when off).
bool write_port_file(const std::string& path, int port, int metrics_port, int http_port) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << port << "\n";
    out << metrics_port << "\n" << http_port << "\n";
    if (!out.flush()) return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  return !ec;
}

// The --config file is read before the other options are registered, so that its values become
// their defaults (flags and environment variables then override them).
std::string config_file_argument(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--config" && i + 1 < argc) return argv[i + 1];
    if (arg.rfind("--config=", 0) == 0) return arg.substr(9);
  }
  const char* env = std::getenv("MESH4D_CONFIG");
  return env ? env : "";
}

std::shared_ptr<grpc::ServerCredentials> credentials(const mesh4d::server::ServerOptions& o) {
  if (o.tls_cert.empty() && o.tls_key.empty()) return grpc::InsecureServerCredentials();
  if (o.tls_cert.empty() || o.tls_key.empty())
    throw std::runtime_error("TLS needs both --tls-cert and --tls-key");
  auto read = [](const std::string& path) {
    std::ifstream in(path);
    if (!in) throw std::runtime_error("cannot read " + path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  grpc::SslServerCredentialsOptions ssl;
  ssl.pem_key_cert_pairs.push_back({read(o.tls_key), read(o.tls_cert)});
  return grpc::SslServerCredentials(ssl);
}

}  // namespace

int main(int argc, char** argv) {
  using namespace mesh4d::server;
  const mesh4d::wire::GrpcLibrary grpc_library;  // first in, last out
  // Jobs allocate and free large arrays (triangulation blocks, uploads, meshes). glibc raises its
  // mmap threshold each time such an array is freed, so that later ones come from the heap, where
  // the long-lived job records between them keep freed memory from going back. A fixed
  // threshold keeps every large array in its own mapping, returned when freed.
  ::mallopt(M_MMAP_THRESHOLD, 256 * 1024);
  ServerOptions options;
  configure_logging(LogFormat::json);
  CLI::App app{"mesh4d-server: meshes 4D label images into pentatope meshes, over gRPC"};
  try {
    const std::string config = config_file_argument(argc, argv);
    if (!config.empty()) load_config_file(config, options);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  add_server_options(app, options);
  CLI11_PARSE(app, argc, argv);
  configure_logging(parse_log_format(options.log_format));

  // Block the stop signals before gRPC starts its threads, so only sigwait below receives them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  std::unique_ptr<JobStore> store;
  try {
    store = std::make_unique<JobStore>(options.data_dir);
  } catch (const std::exception& e) {
    spdlog::error("cannot use the data directory {}: {}", options.data_dir, e.what());
    return 2;
  }
  ManagerConfig config;
  // Every core to a lone job, fewer per job as the queue grows (core_allocator.h); the two
  // options cap that.
  config.cores = std::max(1u, std::thread::hardware_concurrency());
  config.running_jobs = options.running_jobs ? options.running_jobs : config.cores;
  config.threads_per_job = options.threads_per_job ? options.threads_per_job : config.cores;
  config.max_queued_jobs = options.max_queued_jobs;
  config.max_image_bytes = options.max_image_mb << 20;
  config.max_vertex_budget = options.max_vertex_budget;
  config.retention = std::chrono::seconds(static_cast<long long>(options.retention_hours * 3600));
  // One certificate for every port: the civetweb ones (REST, metrics) take it before they start.
  if (!options.tls_cert.empty() || !options.tls_key.empty()) {
    if (options.tls_cert.empty() || options.tls_key.empty()) {
      spdlog::error("TLS needs both --tls-cert and --tls-key");
      return 2;
    }
    if (!options.http_listen.empty() || !options.metrics_listen.empty()) {
      try {
        enable_civetweb_tls(options.tls_cert, options.tls_key);
      } catch (const std::exception& e) {
        spdlog::error("{}", e.what());
        return 2;
      }
    }
  }
  const char* web_scheme = civetweb_tls_enabled() ? "https" : "http";
  std::unique_ptr<ServiceMetrics> metrics;
  if (!options.metrics_listen.empty()) {
    try {
      metrics = std::make_unique<ServiceMetrics>(options.metrics_listen);
    } catch (const std::exception& e) {
      spdlog::error("cannot serve metrics on {}: {}", options.metrics_listen, e.what());
      return 2;
    }
    spdlog::info("metrics on {}://{}/metrics", web_scheme,
                 bound_address(options.metrics_listen, metrics->port()));
  }
  JobManager jobs(*store, config, metrics.get());
  for (const auto& problem : jobs.start()) spdlog::warn("{}", problem);
  MeshService service(jobs, options.token, metrics.get());
  std::unique_ptr<RestApi> rest;
  if (!options.http_listen.empty()) {
    try {
      rest = std::make_unique<RestApi>(jobs, options.http_listen, options.token,
                                       config.max_image_bytes + (1u << 20), metrics.get());
    } catch (const std::exception& e) {
      spdlog::error("{}", e.what());
      return 2;
    }
    spdlog::info("REST API and dashboard on {}://{}/", web_scheme,
                 bound_address(options.http_listen, rest->port()));
  }

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  try {
    builder.AddListeningPort(options.listen, credentials(options), &port);
  } catch (const std::exception& e) {
    spdlog::error("{}", e.what());
    return 2;
  }
  builder.RegisterService(&service);
  builder.SetMaxReceiveMessageSize(64 << 20);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    spdlog::error("cannot listen on {} (address in use or invalid?)", options.listen);
    return 2;
  }
  spdlog::info("mesh4d-server listening on {}, data in {}", bound_address(options.listen, port),
               options.data_dir);
  if (!options.port_file.empty() &&
      !write_port_file(options.port_file, port, metrics ? metrics->port() : 0,
                       rest ? rest->port() : 0)) {
    spdlog::error("cannot write port file {}", options.port_file);
    server->Shutdown();
    return 2;
  }

  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  spdlog::info("signal {} received: shutting down", signal_number);
  // No job starts from here on; the running one stops at its next check and runs again at the
  // restart; every watch ends, so the faces close at once.
  jobs.stop();
  {
    ListenerWaker waker({rest ? rest->port() : 0, metrics ? metrics->port() : 0});
    rest.reset();
    server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(5));
    metrics.reset();
  }
  spdlog::info("stopped");
  return 0;
}
