#include "server_options.h"

#include <CLI/CLI.hpp>

namespace mesh4d::server {

void add_server_options(CLI::App& app, ServerOptions& options) {
  app.add_option("--listen", options.listen, "gRPC address host:port (port 0: any free port)")
      ->envname("MESH4D_LISTEN")
      ->capture_default_str();
  app.add_option("--port-file", options.port_file,
                 "write the bound gRPC port to this file once serving")
      ->envname("MESH4D_PORT_FILE");
}

}  // namespace mesh4d::server
