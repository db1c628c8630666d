#include "job_calls.h"

#include <google/protobuf/util/json_util.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

#include "exit_codes.h"
#include "job_printing.h"
#include "mesh/mesh_io.h"
#include "wire/digest.h"

namespace mesh4d::client {

int watch_job(const GlobalOptions& global, const std::string& id, v1::Job* final) {
  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global, false);  // a job may run for hours: no deadline on the stream
  v1::WatchJobRequest request;
  request.set_job_id(id);
  auto reader = stub->WatchJob(&context, request);
  const bool live = isatty(STDERR_FILENO);
  v1::Job job;
  v1::JobEvent event;
  bool printed_live = false;
  while (reader->Read(&event)) {
    switch (event.event_case()) {
      case v1::JobEvent::kSnapshot:
        job = event.snapshot();
        if (!live) print_job_line(std::cerr, job);
        break;
      case v1::JobEvent::kState:
        job.set_state(event.state());
        if (printed_live) std::cerr << "\n", printed_live = false;
        std::cerr << "state " << v1::JobState_Name(event.state()) << "\n";
        break;
      case v1::JobEvent::kProgress:
        *job.mutable_progress() = event.progress();
        print_progress(std::cerr, event.progress(), live);
        printed_live = live;
        break;
      case v1::JobEvent::kFinished:
        *job.mutable_stats() = event.finished();
        break;
      default:
        break;
    }
  }
  if (printed_live) std::cerr << "\n";
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return report_rpc_error("watch " + id, status, global);
  // The last state event says how it ended; the error text is in the job record.
  if (job.state() != v1::JOB_STATE_SUCCEEDED) {
    grpc::ClientContext get_context;
    prepare(get_context, global);
    v1::GetJobRequest get;
    get.set_job_id(id);
    if (stub->GetJob(&get_context, get, &job).ok() && !job.error().empty())
      std::cerr << "mesh4d-client: job " << id << " " << v1::JobState_Name(job.state()) << ": "
                << job.error() << "\n";
  }
  if (final) *final = job;
  return job.state() == v1::JOB_STATE_SUCCEEDED ? kExitOk : kExitJobFailed;
}

int fetch_result(const GlobalOptions& global, const std::string& id, const std::string& path) {
  auto stub = v1::MeshService::NewStub(open_channel(global));
  grpc::ClientContext context;
  prepare(context, global, false);
  v1::GetResultRequest request;
  request.set_job_id(id);
  auto reader = stub->GetResult(&context, request);
  v1::GetResultResponse message;
  v1::ResultHeader header;
  std::string mesh;
  bool have_header = false;
  while (reader->Read(&message)) {
    if (message.has_header()) {
      header = message.header();
      have_header = true;
      mesh.reserve(header.byte_size());
    } else {
      mesh += message.chunk();
    }
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok()) return report_rpc_error("fetch " + id, status, global);
  if (!have_header || mesh.size() != header.byte_size() || header.sha256() != wire::sha256(mesh)) {
    std::cerr << "mesh4d-client: fetch " << id
              << ": the mesh arrived incomplete or corrupted (size or SHA-256 differ)\n";
    return kExitServerError;
  }
  const std::string tmp = path + ".part";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(mesh.data(), static_cast<std::streamsize>(mesh.size()));
    if (!out.flush()) {
      std::cerr << "mesh4d-client: cannot write " << tmp << "\n";
      return kExitLocal;
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::cerr << "mesh4d-client: cannot write " << path << ": " << ec.message() << "\n";
    return kExitLocal;
  }
  for (const auto& w : header.warnings()) std::cerr << "warning: " << w << "\n";
  std::cerr << "wrote " << path << " (" << mesh.size() << " bytes)\n";
  // The result's report travels with the mesh: its statistics and fidelity certificate (the
  // REST face's field names), its warnings and its checksum.
  std::string stats;
  google::protobuf::util::JsonPrintOptions options;
  options.preserve_proto_field_names = true;
  google::protobuf::util::MessageToJsonString(header.stats(), &stats, options);
  nlohmann::json report = {
      {"job_id", id},
      {"sha256", wire::sha256_hex(mesh)},
      {"byte_size", mesh.size()},
      {"warnings", std::vector<std::string>(header.warnings().begin(), header.warnings().end())},
      {"stats", nlohmann::json::parse(stats, nullptr, false)}};
  const std::string report_path = path + ".report.json";
  std::ofstream(report_path) << report.dump(2) << "\n";
  std::cerr << "wrote " << report_path << " (statistics and fidelity certificate)\n";
  return kExitOk;
}

}  // namespace mesh4d::client
