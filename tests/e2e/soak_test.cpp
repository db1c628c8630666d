// The service under a sustained mixed load on both faces (loopback, bounded in time): gRPC and
// REST clients submit, watch, fetch and cancel jobs while another sends bad requests of every
// kind. The server must refuse each bad request with its status, lose no accepted job, serve
// every result with its checksum, stay up, and end with its memory near where it started.
// MESH4D_SOAK_SECONDS sets the load's length (default 60); the report goes to stdout.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <fstream>
#include <map>
#include <mutex>
#include <random>
#include <set>
#include <thread>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "http_client.h"
#include "server_fixture.h"
#include "wire/digest.h"

namespace mesh4d::testing {
namespace {

using Clock = std::chrono::steady_clock;

long resident_mib(pid_t pid, const char* field = "VmRSS:") {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(field, 0) == 0) return std::stol(line.substr(std::strlen(field))) / 1024;
  return -1;
}

// What the clients saw, shared by their threads.
struct Ledger {
  std::mutex mutex;
  std::set<std::string> accepted;     // every job id a submission got back
  std::map<std::string, int> counts;  // what was done, by name
  std::vector<std::string> problems;  // anything the server did wrong
  void count(const std::string& what) {
    std::lock_guard lock(mutex);
    ++counts[what];
  }
  void accept(const std::string& id, const char* face) {
    std::lock_guard lock(mutex);
    accepted.insert(id);
    ++counts[std::string("accepted via ") + face];
  }
  void problem(const std::string& what) {
    std::lock_guard lock(mutex);
    if (problems.size() < 50) problems.push_back(what);
  }
};

// The results a client fetches must match the checksum the job carries.
void fetch_result(v1::MeshService::Stub& stub, const std::string& id, Ledger& ledger) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(60));
  v1::GetResultRequest request;
  request.set_job_id(id);
  auto reader = stub.GetResult(&context, request);
  std::string mesh, expected;
  for (v1::GetResultResponse part; reader->Read(&part);) {
    if (part.has_header()) expected = part.header().sha256();
    mesh += part.chunk();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok())
    ledger.problem("GetResult " + id + ": " + status.error_message());
  else if (expected.empty() || wire::sha256(mesh) != expected)
    ledger.problem("GetResult " + id + ": the mesh does not match its checksum");
  else
    ledger.count("results fetched and checked");
}

// Watches a job to its end; the last event must be a terminal state.
void watch(v1::MeshService::Stub& stub, const std::string& id, Ledger& ledger) {
  grpc::ClientContext context;
  context.set_deadline(std::chrono::system_clock::now() + std::chrono::seconds(120));
  v1::WatchJobRequest request;
  request.set_job_id(id);
  auto reader = stub.WatchJob(&context, request);
  v1::JobState last = v1::JOB_STATE_UNSPECIFIED;
  for (v1::JobEvent event; reader->Read(&event);) {
    if (event.has_snapshot()) last = event.snapshot().state();
    if (event.has_state()) last = event.state();
  }
  const grpc::Status status = reader->Finish();
  if (!status.ok() || last < v1::JOB_STATE_SUCCEEDED)
    ledger.problem("WatchJob " + id + " ended without a final state: " + status.error_message());
  else
    ledger.count("watches to the end");
  if (last == v1::JOB_STATE_SUCCEEDED) fetch_result(stub, id, ledger);
}

void grpc_client(const RunningServer& server, int client, Clock::time_point end, Ledger& ledger) {
  auto stub = server.stub();
  std::mt19937 random(static_cast<unsigned>(client));
  for (int k = 0; Clock::now() < end; ++k) {
    const std::size_t n = 12 + random() % 8;
    const auto image = domain::hypersphere_phantom({n, n, n, n}, {1, 1, 1, 1}, double(n) / 3);
    const Upload upload = make_upload(image, 1.5 + (random() % 3) * 0.5,
                                      "soak-" + std::to_string(client) + "-" + std::to_string(k));
    v1::SubmitJobResponse response;
    const grpc::Status status = submit(*stub, upload.spec, upload.data, &response);
    if (status.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED) {
      ledger.count("submissions refused: queue full");
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      continue;
    }
    if (!status.ok()) {
      ledger.problem("SubmitJob: " + status.error_message());
      continue;
    }
    const std::string id = response.job().id();
    ledger.accept(id, "gRPC");
    if (k % 4 == 1) {
      grpc::ClientContext context;
      v1::CancelJobRequest request;
      request.set_job_id(id);
      v1::Job job;
      if (stub->CancelJob(&context, request, &job).ok())
        ledger.count("cancels");
      else
        ledger.problem("CancelJob " + id + " refused");
    }
    watch(*stub, id, ledger);
  }
}

void rest_client(const RunningServer& server, const std::string& dir, Clock::time_point end,
                 Ledger& ledger) {
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
  const std::string ball = dir + "/ball.nii.gz";
  domain::write_nifti(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5.5), ball);
  while (Clock::now() < end) {
    const Http submitted = curl(dir, base + "/v1/jobs?delta=2", {"--data-binary", "@" + ball});
    if (submitted.status == 429) {
      ledger.count("submissions refused: queue full");
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
      continue;
    }
    const auto json = submitted.json();
    if (submitted.status != 201 && submitted.status != 200) {
      ledger.problem("POST /v1/jobs: " + std::to_string(submitted.status) + " " + submitted.body);
      continue;
    }
    const std::string id = json["job"]["id"];
    ledger.accept(id, "REST");
    // A short look at the event stream, then polling until the job ends.
    const Http events = curl(dir, base + "/v1/jobs/" + id + "/events", {"--max-time", "1"});
    if (events.headers.rfind("HTTP/1.1 200", 0) != 0 ||
        events.body.find("event:") == std::string::npos)
      ledger.problem("GET events " + id + ": no event stream");
    std::string state;
    for (int poll = 0; poll < 600 && Clock::now() < end + std::chrono::seconds(60); ++poll) {
      state = curl(dir, base + "/v1/jobs/" + id).json().value("state", "");
      if (state != "JOB_STATE_QUEUED" && state != "JOB_STATE_RUNNING") break;
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    if (state != "JOB_STATE_SUCCEEDED") {
      ledger.problem("REST job " + id + " ended " + state);
      continue;
    }
    const Http mesh = curl(dir, base + "/v1/jobs/" + id + "/mesh");
    if (mesh.status != 200 || wire::sha256_hex(mesh.body) != header(mesh, "X-Mesh4d-SHA256"))
      ledger.problem("GET mesh " + id + ": status " + std::to_string(mesh.status) +
                     " or a checksum mismatch");
    else
      ledger.count("results fetched and checked");
  }
}

// Opens a connection, sends part of a request and hangs up.
void half_request(int port, const std::string& part) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) [[maybe_unused]]
    const auto sent = ::send(fd, part.data(), part.size(), MSG_NOSIGNAL);
  ::close(fd);
}

// Every kind of bad request, in turn, each with the status it must get.
void bad_client(const RunningServer& server, const std::string& dir, Clock::time_point end,
                Ledger& ledger) {
  auto stub = server.stub();
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
  const std::string garbage = dir + "/garbage.nii";
  std::ofstream(garbage) << std::string(2000, 'x');
  const std::string nrrd = dir + "/short.nrrd";
  std::ofstream(nrrd, std::ios::binary)
      << "NRRD0004\ntype: uint8\ndimension: 4\nsizes: 9 9 9 9\nencoding: raw\n\n"
      << "\1\1";
  const std::string mha = dir + "/elsewhere.mha";
  std::ofstream(mha) << "ObjectType = Image\nNDims = 4\nDimSize = 2 2 2 2\n"
                        "ElementType = MET_UCHAR\nElementDataFile = /etc/hostname\n";
  const auto expect = [&](const std::string& what, int got, int wanted) {
    if (got == wanted)
      ledger.count("bad requests refused as they should be");
    else
      ledger.problem(what + ": status " + std::to_string(got) + ", wanted " +
                     std::to_string(wanted));
  };
  const auto image = domain::hypersphere_phantom({8, 8, 8, 8}, {1, 1, 1, 1}, 3);
  for (int k = 0; Clock::now() < end; ++k) {
    switch (k % 8) {
      case 0: {  // a checksum that does not match the data
        Upload upload = make_upload(image, 2, "");
        upload.spec.mutable_image()->set_sha256(std::string(32, '\0'));
        v1::SubmitJobResponse response;
        expect("gRPC bad checksum", submit(*stub, upload.spec, upload.data, &response).error_code(),
               grpc::StatusCode::INVALID_ARGUMENT);
        break;
      }
      case 1: {
        grpc::ClientContext context;
        v1::GetJobRequest request;
        request.set_job_id("no-such-job");
        v1::Job job;
        expect("gRPC unknown job", stub->GetJob(&context, request, &job).error_code(),
               grpc::StatusCode::NOT_FOUND);
        break;
      }
      case 2:
        expect("REST garbage body",
               curl(dir, base + "/v1/jobs", {"--data-binary", "@" + garbage}).status, 400);
        break;
      case 3:
        expect("REST short NRRD",
               curl(dir, base + "/v1/jobs", {"--data-binary", "@" + nrrd}).status, 400);
        break;
      case 4:
        expect("REST MetaImage naming a server file",
               curl(dir, base + "/v1/jobs", {"--data-binary", "@" + mha}).status, 400);
        break;
      case 5:
        expect("REST negative delta",
               curl(dir, base + "/v1/jobs?delta=-1", {"--data-binary", "@" + dir + "/ball.nii.gz"})
                   .status,
               400);
        break;
      case 6:
        expect("REST unknown job", curl(dir, base + "/v1/jobs/no-such-job").status, 404);
        break;
      case 7:
        half_request(server.http_port(),
                     "POST /v1/jobs HTTP/1.1\r\nContent-Length: 99999\r\n\r\nab");
        half_request(server.http_port(), "GET /v1/jo");
        ledger.count("connections dropped mid-request");
        break;
    }
  }
}

TEST(Soak, BothFacesUnderMixedLoadLoseNothingAndReturnTheirMemory) {
  const char* env = std::getenv("MESH4D_SOAK_SECONDS");
  const int seconds = env ? std::atoi(env) : 60;
  const std::string dir = make_temp_dir("mesh4d-soak");
  RunningServer server(dir + "/data", {"--running-jobs", "2", "--max-queued-jobs", "6"});
  ASSERT_FALSE(server.address().empty()) << "the server did not start";
  const pid_t pid = server.process().pid();
  Ledger ledger;
  // Warm-up: one job through each face, so that what the server allocates once is in the
  // baseline.
  rest_client(server, dir, Clock::now(), ledger);
  {
    auto stub = server.stub();
    const Upload upload =
        make_upload(domain::hypersphere_phantom({10, 10, 10, 10}, {1, 1, 1, 1}, 3.5), 2, "warm-up");
    v1::SubmitJobResponse response;
    ASSERT_TRUE(submit(*stub, upload.spec, upload.data, &response).ok());
    ledger.accept(response.job().id(), "gRPC");
    watch(*stub, response.job().id(), ledger);
  }
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const long baseline = resident_mib(pid);

  std::atomic<bool> done = false;
  std::atomic<long> peak = baseline;
  std::thread sampler([&] {
    while (!done) {
      peak = std::max(peak.load(), resident_mib(pid));
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  const auto end = Clock::now() + std::chrono::seconds(seconds);
  std::vector<std::thread> clients;
  for (int c = 0; c < 3; ++c) clients.emplace_back([&, c] { grpc_client(server, c, end, ledger); });
  for (int c = 0; c < 2; ++c)
    clients.emplace_back([&, c] {
      const std::string own = dir + "/rest" + std::to_string(c);
      std::filesystem::create_directories(own);
      rest_client(server, own, end, ledger);
    });
  clients.emplace_back([&] { bad_client(server, dir, end, ledger); });
  for (auto& t : clients) t.join();

  // Every accepted job is listed, ended, and (if it succeeded) its result is served.
  auto stub = server.stub();
  std::map<std::string, int> states;
  for (const std::string& id : ledger.accepted) {
    const v1::Job job = wait_until_done(*stub, id, std::chrono::seconds(120));
    ++states[v1::JobState_Name(job.state())];
    if (job.id() != id || job.state() < v1::JOB_STATE_SUCCEEDED)
      ledger.problem("job " + id + " lost or not ended");
  }
  std::set<std::string> listed;
  v1::ListJobsRequest list;
  for (;;) {
    grpc::ClientContext context;
    v1::ListJobsResponse page;
    ASSERT_TRUE(stub->ListJobs(&context, list, &page).ok());
    for (const auto& job : page.jobs()) listed.insert(job.id());
    if (page.next_page_token().empty()) break;
    list.set_page_token(page.next_page_token());
  }
  for (const std::string& id : ledger.accepted)
    if (!listed.count(id)) ledger.problem("job " + id + " is missing from ListJobs");
  std::this_thread::sleep_for(std::chrono::seconds(2));
  done = true;
  sampler.join();
  const long final_rss = resident_mib(pid);

  std::cout << "soak: " << seconds << " s, 3 gRPC + 2 REST clients + 1 bad-request client\n";
  for (const auto& [what, n] : ledger.counts) std::cout << "  " << what << ": " << n << "\n";
  for (const auto& [state, n] : states) std::cout << "  jobs " << state << ": " << n << "\n";
  std::cout << "  server memory (RSS, MiB): baseline " << baseline << ", peak " << peak
            << ", at the end " << final_rss << "\n";
  for (const std::string& p : ledger.problems) ADD_FAILURE() << p;
  EXPECT_EQ(::kill(pid, 0), 0) << "the server is gone";
  EXPECT_GE(ledger.counts["results fetched and checked"], 3);
  EXPECT_GE(ledger.counts["bad requests refused as they should be"], 8);
  // Back near the start: what a finished job used is returned, whatever the run's length.
  EXPECT_LE(final_rss, baseline + 64) << "peak " << peak;
}

}  // namespace
}  // namespace mesh4d::testing
