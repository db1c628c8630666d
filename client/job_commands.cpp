// status, list, cancel, delete, watch, fetch: one call each.
#include "job_commands.h"

#include <CLI/CLI.hpp>
#include <cctype>
#include <functional>
#include <iostream>

#include "connection.h"
#include "exit_codes.h"
#include "job_calls.h"
#include "job_printing.h"
#include "mesh4d/v1/mesh4d.grpc.pb.h"

namespace mesh4d::client {
namespace {

int run_status(const GlobalOptions& global, const std::string& id) {
  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global);
  v1::GetJobRequest request;
  request.set_job_id(id);
  v1::Job job;
  const grpc::Status status = stub->GetJob(&context, request, &job);
  if (!status.ok()) return report_rpc_error("status " + id, status, global);
  print_job_line(std::cout, job);
  std::cout << "  delta " << job.params().delta() << ", time scale " << job.params().time_scale()
            << " per frame, "
            << (job.params().time_topology() == v1::TIME_TOPOLOGY_PERIODIC ? "periodic" : "open")
            << " time, sag offset " << (job.params().sag_offset() ? "on" : "off") << "\n";
  if (job.state() == v1::JOB_STATE_SUCCEEDED) print_stats(std::cout, job.stats());
  for (const auto& w : job.warnings()) std::cout << "  warning: " << w << "\n";
  return kExitOk;
}

int run_list(const GlobalOptions& global, const std::string& state_name) {
  v1::JobState state = v1::JOB_STATE_UNSPECIFIED;
  std::string upper = state_name;
  for (char& c : upper) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (!state_name.empty() && !v1::JobState_Parse("JOB_STATE_" + upper, &state)) {
    std::cerr << "mesh4d-client: list: unknown state '" << state_name
              << "' (queued, running, succeeded, failed, cancelled)\n";
    return kExitUsage;
  }
  auto stub = v1::MeshService::NewStub(open_channel(global));
  v1::ListJobsRequest request;
  request.set_state(state);
  do {
    grpc::ClientContext context;
    prepare(context, global);
    v1::ListJobsResponse response;
    const grpc::Status status = stub->ListJobs(&context, request, &response);
    if (!status.ok()) return report_rpc_error("list", status, global);
    for (const auto& job : response.jobs()) print_job_line(std::cout, job);
    request.set_page_token(response.next_page_token());
  } while (!request.page_token().empty());
  return kExitOk;
}

int run_cancel(const GlobalOptions& global, const std::string& id) {
  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global);
  v1::CancelJobRequest request;
  request.set_job_id(id);
  v1::Job job;
  const grpc::Status status = stub->CancelJob(&context, request, &job);
  if (!status.ok()) return report_rpc_error("cancel " + id, status, global);
  print_job_line(std::cout, job);
  return kExitOk;
}

int run_delete(const GlobalOptions& global, const std::string& id) {
  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global);
  v1::DeleteJobRequest request;
  request.set_job_id(id);
  v1::DeleteJobResponse response;
  const grpc::Status status = stub->DeleteJob(&context, request, &response);
  if (!status.ok()) return report_rpc_error("delete " + id, status, global);
  std::cout << "deleted " << id << "\n";
  return kExitOk;
}

// A subcommand taking one job id and running `body` on it.
void add_id_command(CLI::App& app, const char* name, const char* help, int* exit_code,
                    std::function<int(const std::string&)> body) {
  auto id = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand(name, help);
  cmd->add_option("ID", *id, "job id")->required();
  cmd->callback([id, body, exit_code] { *exit_code = body(*id); });
}

}  // namespace

void setup_job_commands(CLI::App& app, const GlobalOptions& global, int* exit_code) {
  add_id_command(app, "status", "show a job (and its quality table once done)", exit_code,
                 [&global](const std::string& id) { return run_status(global, id); });
  add_id_command(app, "cancel", "cancel a queued or running job", exit_code,
                 [&global](const std::string& id) { return run_cancel(global, id); });
  add_id_command(app, "delete", "delete a job and its result", exit_code,
                 [&global](const std::string& id) { return run_delete(global, id); });
  auto state = std::make_shared<std::string>();
  CLI::App* list = app.add_subcommand("list", "list jobs, oldest first");
  list->add_option("--state", *state, "only jobs in this state (queued, running, succeeded, ...)");
  list->callback([&global, state, exit_code] { *exit_code = run_list(global, *state); });
}

void setup_watch_command(CLI::App& app, const GlobalOptions& global, int* exit_code) {
  add_id_command(app, "watch", "follow a job's progress until it ends", exit_code,
                 [&global](const std::string& id) { return watch_job(global, id, nullptr); });
}

void setup_fetch_command(CLI::App& app, const GlobalOptions& global, int* exit_code) {
  auto id = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  CLI::App* cmd = app.add_subcommand("fetch", "download the mesh of a finished job");
  cmd->add_option("ID", *id, "job id")->required();
  cmd->add_option("--out", *out, "where to write the .m4d mesh")->required();
  cmd->callback([&global, id, out, exit_code] { *exit_code = fetch_result(global, *id, *out); });
}

}  // namespace mesh4d::client
