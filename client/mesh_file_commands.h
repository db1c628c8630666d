// The subcommands that work on a downloaded .m4d mesh, without a server: export (time slices
// as VTK, the whole mesh for MFEM or libMeshb) and stats (the quality table).
#pragma once

namespace CLI {
class App;
}

namespace mesh4d::client {

void setup_export_command(CLI::App& app, int* exit_code);
void setup_stats_command(CLI::App& app, int* exit_code);

}  // namespace mesh4d::client
