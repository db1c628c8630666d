// `mesh4d-client health`: asks the server's standard grpc.health.v1 service whether it serves.
#pragma once

namespace CLI {
class App;
}

namespace mesh4d::client {

struct GlobalOptions;

/// Adds the subcommand to `app`; when run, it stores its exit code in `*exit_code`.
void setup_health_command(CLI::App& app, const GlobalOptions& global, int* exit_code);

}  // namespace mesh4d::client
