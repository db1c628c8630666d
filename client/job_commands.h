// The subcommands that act on one job or list them: status, list, cancel, delete, watch, fetch;
// and submit, which uploads an image and, with --wait, watches and fetches.
#pragma once

namespace CLI {
class App;
}

namespace mesh4d::client {

struct GlobalOptions;

void setup_job_commands(CLI::App& app, const GlobalOptions& global, int* exit_code);
void setup_watch_command(CLI::App& app, const GlobalOptions& global, int* exit_code);
void setup_fetch_command(CLI::App& app, const GlobalOptions& global, int* exit_code);
void setup_submit_command(CLI::App& app, const GlobalOptions& global, int* exit_code);

}  // namespace mesh4d::client
