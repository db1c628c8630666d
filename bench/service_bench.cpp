// service_bench: what the service costs on top of the engine. The real mesh4d-server runs on a
// loopback port (one job at a time, one thread per job); for each phantom, the same upload is
// meshed in this process (decode, oracle, refine, encode: the reference) and through the
// service (submit, watch, fetch), and the table gives medians of both and their ratio, and the
// latencies a pipeline sees: submit acknowledged, first event of the watch opened right after,
// first progress event. Goal: first event under 50 ms.
//
//   service_bench [--repeats N]
#include <grpcpp/grpcpp.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../tests/e2e/process.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh_io.h"
#include "mesh4d/v1/mesh4d.grpc.pb.h"
#include "refine/refiner.h"
#include "wire/grpc_library.h"
#include "wire/submit_stream.h"
#include "wire/upload_codec.h"

using namespace mesh4d;
using Clock = std::chrono::steady_clock;

namespace {

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Case {
  const char* name;
  domain::LabelImage4 image;
  double delta;
};

// The engine alone on the upload, as the server's runner does it.
double in_process_ms(const v1::ImageHeader& header, const std::string& raw, double delta,
                     std::uint64_t* pentatopes) {
  const auto t0 = Clock::now();
  std::vector<std::string> warnings;
  const domain::LabelImage4 image = wire::decode_upload(header, raw, &warnings);
  const domain::SurfaceOracle oracle(image);
  refine::RefineParams params;
  params.delta = delta;
  refine::Refiner refiner(oracle, params);
  const auto result = refiner.run();
  [[maybe_unused]] const auto bytes = mesh::encode_m4d(result.mesh);  // as the server does
  *pentatopes = result.stats.pentatopes;
  return ms_since(t0);
}

struct ServiceTimes {
  double ack_ms = 0, first_event_ms = 0, first_progress_ms = 0, total_ms = 0;
  bool ok = false;
};

ServiceTimes through_service(v1::MeshService::Stub& stub, const v1::JobSpec& spec,
                             const std::string& raw) {
  ServiceTimes t;
  const auto t0 = Clock::now();
  v1::SubmitJobResponse response;
  {
    grpc::ClientContext context;
    const grpc::Status status = wire::submit_job(stub, context, spec, raw, &response);
    if (!status.ok()) {
      std::fprintf(stderr, "submit: %s\n", status.error_message().c_str());
      return t;
    }
  }
  t.ack_ms = ms_since(t0);
  {
    grpc::ClientContext context;
    v1::WatchJobRequest request;
    request.set_job_id(response.job().id());
    auto reader = stub.WatchJob(&context, request);
    v1::JobEvent event;
    bool succeeded = false;
    while (reader->Read(&event)) {
      if (t.first_event_ms == 0) t.first_event_ms = ms_since(t0);
      if (event.has_progress() && t.first_progress_ms == 0) t.first_progress_ms = ms_since(t0);
      if (event.has_state() && event.state() >= v1::JOB_STATE_SUCCEEDED) {
        succeeded = event.state() == v1::JOB_STATE_SUCCEEDED;
        break;
      }
    }
    context.TryCancel();
    if (!succeeded) return t;
  }
  {
    grpc::ClientContext context;
    v1::GetResultRequest request;
    request.set_job_id(response.job().id());
    auto reader = stub.GetResult(&context, request);
    v1::GetResultResponse message;
    std::size_t bytes = 0;
    while (reader->Read(&message)) bytes += message.chunk().size();
    if (!reader->Finish().ok() || bytes == 0) return t;
  }
  t.total_ms = ms_since(t0);
  t.ok = true;
  return t;
}

}  // namespace

int main(int argc, char** argv) {
  const mesh4d::wire::GrpcLibrary grpc_library;  // first in, last out
  int repeats = 5;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--repeats") == 0) repeats = std::max(1, std::atoi(argv[i + 1]));

  const std::string dir = testing::make_temp_dir("mesh4d-service-bench");
  const std::string port_file = dir + "/port";
  testing::ChildProcess server(
      {MESH4D_SERVER_BIN, "--listen", "127.0.0.1:0", "--port-file", port_file, "--data-dir",
       dir + "/data", "--threads-per-job", "1", "--metrics-listen", "", "--http-listen", "",
       "--max-queued-jobs", "64"},
      dir + "/server.log");
  const std::string port = testing::wait_for_file(port_file, std::chrono::seconds(20));
  if (port.empty()) {
    std::fprintf(stderr, "the server did not start; see %s/server.log\n", dir.c_str());
    return 1;
  }
  auto stub = v1::MeshService::NewStub(grpc::CreateChannel(
      "127.0.0.1:" + std::to_string(std::stoi(port)), grpc::InsecureChannelCredentials()));

  std::vector<Case> cases;
  cases.push_back({"tiny sphere 16^4 r=5, delta 3",
                   domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5), 3});
  cases.push_back({"hypersphere 32^4 r=12, delta 2",
                   domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12), 2});

  std::printf("service_bench: medians of %d runs; mesh4d-server on 127.0.0.1, 1 thread a job\n\n",
              repeats);
  std::printf("| %-31s | %10s | %11s | %9s | %11s | %14s | %11s | %8s |\n", "phantom", "pentatopes",
              "in-process", "submit ok", "first event", "first progress", "end to end", "overhead");
  std::printf(
      "|%s|%s|%s|%s|%s|%s|%s|%s|\n", std::string(33, '-').c_str(), std::string(12, '-').c_str(),
      std::string(13, '-').c_str(), std::string(11, '-').c_str(), std::string(13, '-').c_str(),
      std::string(16, '-').c_str(), std::string(13, '-').c_str(), std::string(10, '-').c_str());
  int request = 0;
  for (const Case& c : cases) {
    v1::JobSpec spec;
    const std::string raw = wire::encode_upload(c.image, spec.mutable_image());
    spec.mutable_params()->set_delta(c.delta);
    std::vector<double> local, ack, first, progress, total;
    std::uint64_t pentatopes = 0;
    for (int r = 0; r < repeats; ++r) {
      local.push_back(in_process_ms(spec.image(), raw, c.delta, &pentatopes));
      spec.set_request_id("bench-" + std::to_string(request++));
      const ServiceTimes t = through_service(*stub, spec, raw);
      if (!t.ok) {
        std::fprintf(stderr, "%s: the job did not succeed; see %s/server.log\n", c.name,
                     dir.c_str());
        return 1;
      }
      ack.push_back(t.ack_ms);
      first.push_back(t.first_event_ms);
      progress.push_back(t.first_progress_ms);
      total.push_back(t.total_ms);
    }
    const double ratio = median(total) / median(local);
    std::printf(
        "| %-31s | %10llu | %8.0f ms | %6.1f ms | %8.1f ms | %11.1f ms | %8.0f ms | %7.2fx |\n",
        c.name, static_cast<unsigned long long>(pentatopes), median(local), median(ack),
        median(first), median(progress), median(total), ratio);
  }
  std::printf(
      "\noverhead = end to end through the service / in-process; goal: first event < 50 ms\n");
  server.stop(SIGTERM);
  return 0;
}
