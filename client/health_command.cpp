#include "health_command.h"

#include <CLI/CLI.hpp>
#include <iostream>

#include "connection.h"
#include "exit_codes.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace mesh4d::client {
namespace {

struct HealthOptions {
  std::string service;  // empty: the server as a whole
};

int run_health(const GlobalOptions& global, const HealthOptions& options) {
  auto stub = grpc::health::v1::Health::NewStub(open_channel(global));
  grpc::ClientContext context;
  context.set_deadline(call_deadline(global));
  context.set_wait_for_ready(false);
  grpc::health::v1::HealthCheckRequest request;
  request.set_service(options.service);
  grpc::health::v1::HealthCheckResponse response;
  const grpc::Status status = stub->Check(&context, request, &response);
  if (!status.ok()) return report_rpc_error("health", status, global);

  std::cout << grpc::health::v1::HealthCheckResponse::ServingStatus_Name(response.status()) << "\n";
  return response.status() == grpc::health::v1::HealthCheckResponse::SERVING ? kExitOk
                                                                             : kExitServerError;
}

}  // namespace

void setup_health_command(CLI::App& app, const GlobalOptions& global, int* exit_code) {
  auto options = std::make_shared<HealthOptions>();
  CLI::App* cmd = app.add_subcommand("health", "check that the server is serving");
  cmd->add_option("--service", options->service, "a service name (default: the whole server)");
  cmd->callback([&global, options, exit_code] { *exit_code = run_health(global, *options); });
}

}  // namespace mesh4d::client
