// mesh4d-client: submits 4D label images to mesh4d-server and fetches meshes. main only dispatches
// to the subcommands, one file each.
#include <CLI/CLI.hpp>

#include "connection.h"
#include "exit_codes.h"
#include "health_command.h"
#include "job_commands.h"
#include "mesh_file_commands.h"
#include "wire/grpc_library.h"

int main(int argc, char** argv) {
  using namespace mesh4d::client;
  const mesh4d::wire::GrpcLibrary grpc_library;  // first in, last out
  CLI::App app{"mesh4d-client: talk to a mesh4d-server"};
  app.require_subcommand(1);
  GlobalOptions global;
  add_global_options(app, global);
  int exit_code = kExitOk;
  setup_health_command(app, global, &exit_code);
  setup_submit_command(app, global, &exit_code);
  setup_watch_command(app, global, &exit_code);
  setup_fetch_command(app, global, &exit_code);
  setup_job_commands(app, global, &exit_code);
  setup_export_command(app, &exit_code);
  setup_stats_command(app, &exit_code);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int cli_code = app.exit(e);  // prints help or the error
    return cli_code == 0 ? kExitOk : kExitUsage;
  }
  return exit_code;
}
