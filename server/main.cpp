// mesh4d-server: starts the gRPC server (health and reflection services) and runs until SIGINT or
// SIGTERM. The meshing service, durable job queue and metrics are registered here as they land
// (issue 7); until then a MeshService call is answered UNIMPLEMENTED by gRPC itself.
#include <grpcpp/ext/proto_server_reflection_plugin.h>
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>

#include "server_options.h"

namespace {

// "host:0" → "host:PORT", for the log line.
std::string bound_address(const std::string& listen, int port) {
  const auto colon = listen.rfind(':');
  return listen.substr(0, colon) + ":" + std::to_string(port);
}

// Written to a temporary file then renamed, so a reader never sees a partial number.
bool write_port_file(const std::string& path, int port) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp, std::ios::trunc);
    out << port << "\n";
    if (!out.flush()) return false;
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  return !ec;
}

}  // namespace

int main(int argc, char** argv) {
  mesh4d::server::ServerOptions options;
  CLI::App app{"mesh4d-server: meshes 4D label images into pentatope meshes, over gRPC"};
  mesh4d::server::add_server_options(app, options);
  CLI11_PARSE(app, argc, argv);

  // Block the stop signals before gRPC starts its threads, so only sigwait below receives them.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  grpc::EnableDefaultHealthCheckService(true);
  grpc::reflection::InitProtoReflectionServerBuilderPlugin();
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(options.listen, grpc::InsecureServerCredentials(), &port);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    spdlog::error("cannot listen on {} (address in use or invalid?)", options.listen);
    return 2;
  }
  spdlog::info("mesh4d-server listening on {}", bound_address(options.listen, port));
  if (!options.port_file.empty() && !write_port_file(options.port_file, port)) {
    spdlog::error("cannot write port file {}", options.port_file);
    server->Shutdown();
    return 2;
  }

  int signal_number = 0;
  sigwait(&stop_signals, &signal_number);
  spdlog::info("signal {} received: shutting down", signal_number);
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(5));
  return 0;
}
