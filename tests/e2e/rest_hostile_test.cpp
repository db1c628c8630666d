// The REST face against hostile and careless clients (curl and raw sockets against the real
// server): each attack of the service-hardening list reproduced, and what the server must do.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <thread>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "http_client.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

// A 4D ball of n voxels a side (radius r) written as NIfTI at `path` (.nii or .nii.gz).
std::string write_ball(const std::string& path, std::size_t n, double r) {
  domain::write_nifti(domain::hypersphere_phantom({n, n, n, n}, {1, 1, 1, 1}, r), path);
  return path;
}

std::string rest_base(const RunningServer& server) {
  return "http://127.0.0.1:" + std::to_string(server.http_port());
}

// The server's peak resident memory so far, in MiB (VmHWM).
long peak_mib(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stol(line.substr(6)) / 1024;
  return -1;
}

// A NIfTI-1 file whose header announces x·y·z·t uint8 voxels, all of them zeros, gzip'ed:
// 256 MiB announced and present inflates from about 256 KB.
void write_zero_nifti_gz(const std::string& dir, const std::string& path,
                         const std::array<std::int16_t, 4>& dims) {
  const std::string small = dir + "/small.nii";
  domain::write_nifti(domain::hypersphere_phantom({8, 8, 8, 2}, {1, 1, 1, 1}, 3), small);
  std::ifstream in(small, std::ios::binary);
  std::string header((std::istreambuf_iterator<char>(in)), {});
  header.resize(352);  // the header and its 4 extension bytes
  std::memcpy(&header[42], dims.data(), sizeof(std::int16_t) * 4);
  gzFile out = gzopen(path.c_str(), "wb1");
  gzwrite(out, header.data(), static_cast<unsigned>(header.size()));
  const std::vector<char> zeros(1 << 20, 0);
  const std::uint64_t bytes = std::uint64_t(dims[0]) * dims[1] * dims[2] * dims[3];
  for (std::uint64_t done = 0; done < bytes; done += zeros.size())
    gzwrite(out, zeros.data(),
            static_cast<unsigned>(std::min<std::uint64_t>(zeros.size(), bytes - done)));
  gzclose(out);
}

// A TCP connection to the server's REST port that sends `request` and keeps the socket open.
class RawConnection {
 public:
  RawConnection(int port, const std::string& request) {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
      ::close(fd_);
      fd_ = -1;
      return;
    }
    ::send(fd_, request.data(), request.size(), MSG_NOSIGNAL);
  }
  ~RawConnection() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawConnection(const RawConnection&) = delete;
  RawConnection& operator=(const RawConnection&) = delete;
  bool connected() const { return fd_ >= 0; }
  // What the server sent within `ms` (up to 4 KiB).
  std::string read_some(int ms) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, ms) <= 0) return "";
    char buffer[4096];
    const ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0);
    return n > 0 ? std::string(buffer, static_cast<std::size_t>(n)) : "";
  }
  // What the server sent until `text` is in it, the connection ends, or `ms` pass.
  std::string read_until(const std::string& text, int ms) {
    std::string all;
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (all.find(text) == std::string::npos && std::chrono::steady_clock::now() < deadline) {
      const std::string more = read_some(ms);
      if (more.empty()) break;
      all += more;
    }
    return all;
  }

 private:
  int fd_ = -1;
};

// 1. A gzip bomb: refused from its header at once, in bounded memory, with a JSON error that
// names no server path.
TEST(RestHostile, GzipBombIsRefusedFromItsHeaderInBoundedMemory) {
  const std::string dir = make_temp_dir("mesh4d-rest-bomb");
  RunningServer server(dir + "/data", {"--max-image-mb", "64"});
  const std::string base = rest_base(server);
  const std::string bomb = dir + "/bomb.nii.gz";
  write_zero_nifti_gz(dir, bomb, {512, 512, 256, 4});
  std::ifstream size(bomb, std::ios::binary | std::ios::ate);
  EXPECT_LT(static_cast<long>(size.tellg()), 4l << 20) << "a small file";
  const long before = peak_mib(server.process().pid());
  const Http h = curl(dir, base + "/v1/jobs?delta=5", {"--data-binary", "@" + bomb});
  EXPECT_EQ(h.status, 429) << h.body;
  EXPECT_EQ(h.json()["code"], "RESOURCE_EXHAUSTED") << h.body;
  EXPECT_NE(h.body.find("268435456 voxels"), std::string::npos) << h.body;
  EXPECT_EQ(h.body.find("/tmp"), std::string::npos) << "no server path in: " << h.body;
  EXPECT_EQ(h.body.find("mesh4d-upload"), std::string::npos) << h.body;
  const long peak = peak_mib(server.process().pid());
  std::printf("server peak memory: %ld MiB before, %ld MiB after the bomb\n", before, peak);
  EXPECT_LT(peak, 512);
  // The server is still there.
  EXPECT_EQ(curl(dir, base + "/v1/jobs").status, 200);
}

// GetResult's status code, reading the stream to its end.
grpc::StatusCode get_result(v1::MeshService::Stub& stub, const std::string& id) {
  grpc::ClientContext context;
  v1::GetResultRequest request;
  request.set_job_id(id);
  auto reader = stub.GetResult(&context, request);
  v1::GetResultResponse message;
  while (reader->Read(&message)) {
  }
  return reader->Finish().error_code();
}

void flip_one_byte(const std::string& path) {
  std::fstream f(path, std::ios::in | std::ios::out | std::ios::binary);
  f.seekg(200);
  char c = 0;
  f.read(&c, 1);
  f.seekp(200);
  c = static_cast<char>(c ^ 0x20);
  f.write(&c, 1);
}

// 3. A stored result altered on disk is never served as valid: not after a restart (checked as
// the job is loaded) and not while the server runs (checked as it is served). The job becomes
// FAILED and says why.
TEST(RestHostile, CorruptResultsAreRefusedAndTheJobSaysWhy) {
  const std::string dir = make_temp_dir("mesh4d-rest-corrupt");
  std::vector<std::string> ids;
  {
    RunningServer server(dir + "/data");
    auto stub = server.stub();
    for (const char* request : {"a", "b", "c", "d"}) {
      const Upload up =
          make_upload(domain::hypersphere_phantom({20, 20, 20, 20}, {1, 1, 1, 1}, 7), 3, request);
      v1::SubmitJobResponse response;
      ASSERT_TRUE(submit(*stub, up.spec, up.data, &response).ok());
      ids.push_back(response.job().id());
    }
    for (const auto& id : ids)
      ASSERT_EQ(wait_until_done(*stub, id).state(), v1::JOB_STATE_SUCCEEDED);
    ASSERT_EQ(get_result(*stub, ids[0]), grpc::StatusCode::OK);
    ASSERT_EQ(server.process().stop(SIGTERM), 0);
  }
  const auto result_file = [&](const std::string& id) {
    return dir + "/data/jobs/" + id + "/result.m4d";
  };
  flip_one_byte(result_file(ids[0]));
  std::filesystem::resize_file(result_file(ids[1]),
                               std::filesystem::file_size(result_file(ids[1])) / 2);
  RunningServer server(dir + "/data");
  auto stub = server.stub();
  const std::string base = rest_base(server);
  for (int k : {0, 1}) {
    SCOPED_TRACE(ids[k]);
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(ids[k]);
    v1::Job job;
    ASSERT_TRUE(stub->GetJob(&context, request, &job).ok());
    EXPECT_EQ(job.state(), v1::JOB_STATE_FAILED);
    EXPECT_NE(job.error().find("corrupt"), std::string::npos) << job.error();
    EXPECT_EQ(get_result(*stub, ids[k]), grpc::StatusCode::FAILED_PRECONDITION);
    EXPECT_EQ(curl(dir, base + "/v1/jobs/" + ids[k] + "/mesh").status, 400);
  }
  // Altered while the server runs: refused as it is served, on either face, and the job fails.
  EXPECT_EQ(curl(dir, base + "/v1/jobs/" + ids[2] + "/mesh").status, 200);
  flip_one_byte(result_file(ids[2]));
  const Http h = curl(dir, base + "/v1/jobs/" + ids[2] + "/mesh");
  EXPECT_EQ(h.status, 500);
  EXPECT_EQ(h.json()["code"], "DATA_LOSS") << h.body;
  EXPECT_EQ(get_result(*stub, ids[2]), grpc::StatusCode::FAILED_PRECONDITION);
  EXPECT_EQ(curl(dir, base + "/v1/jobs/" + ids[2]).json()["state"], "JOB_STATE_FAILED");
  EXPECT_EQ(get_result(*stub, ids[3]), grpc::StatusCode::OK);
  std::filesystem::resize_file(result_file(ids[3]), 100);
  EXPECT_EQ(get_result(*stub, ids[3]), grpc::StatusCode::DATA_LOSS);
  EXPECT_EQ(curl(dir, base + "/v1/jobs/" + ids[3]).json()["state"], "JOB_STATE_FAILED");
}

// 2. Event streams and clients that send half a request do not starve the REST face: with every
// stream the server admits open on a queued job and 60 connections stuck in their headers, a
// listing still answers within 2 s; one stream more is refused (429, JSON), not queued.
TEST(RestHostile, OpenStreamsAndHalfSentHeadersDoNotStarveOtherCalls) {
  const std::string dir = make_temp_dir("mesh4d-rest-starve");
  RunningServer server(dir + "/data", {"--running-jobs", "1"});
  const int port = server.http_port();
  const std::string base = "http://127.0.0.1:" + std::to_string(port);
  const std::string sphere = write_ball(dir + "/sphere.nii.gz", 24, 8);
  // A slow job runs; the next one waits behind it, so its streams stay open.
  const std::string slow = curl(dir, base + "/v1/jobs?delta=0.8&threads=1&vertex_budget=4000000",
                                {"--data-binary", "@" + sphere})
                               .json()["job"]["id"];
  const std::string queued =
      curl(dir, base + "/v1/jobs?delta=3", {"--data-binary", "@" + sphere}).json()["job"]["id"];
  std::vector<std::unique_ptr<RawConnection>> streams;
  std::size_t admitted = 0;
  for (int k = 0; k < 128; ++k) {
    streams.push_back(std::make_unique<RawConnection>(
        port, "GET /v1/jobs/" + queued + "/events HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n"));
    admitted += streams.back()->read_some(5000).rfind("HTTP/1.1 200", 0) == 0;
  }
  EXPECT_EQ(admitted, 128u);
  EXPECT_EQ(curl(dir, base + "/v1/jobs/" + queued).json()["state"], "JOB_STATE_QUEUED")
      << "the streams' job must still wait";
  const Http refused = curl(dir, base + "/v1/jobs/" + queued + "/events", {}, 10);
  EXPECT_EQ(refused.status, 429) << refused.body;
  EXPECT_EQ(refused.json()["code"], "RESOURCE_EXHAUSTED") << refused.body;
  std::vector<std::unique_ptr<RawConnection>> stuck;
  for (int k = 0; k < 60; ++k) {
    stuck.push_back(
        std::make_unique<RawConnection>(port, "GET /v1/jobs HTTP/1.1\r\nHost: 127.0.0.1\r\n"));
    EXPECT_TRUE(stuck.back()->connected());
  }
  const Http listed = curl(dir, base + "/v1/jobs", {"--max-time", "2"}, 10);
  EXPECT_EQ(listed.status, 200) << "no answer within 2 s: " << listed.headers << listed.body;
  // A header never finished is dropped, with a JSON error, once the request timeout passes.
  const std::string dropped = stuck.front()->read_until("\"code\"", 15000);
  EXPECT_EQ(dropped.rfind("HTTP/1.1 4", 0), 0u) << dropped;
  EXPECT_NE(dropped.find("application/json"), std::string::npos) << dropped;
  EXPECT_NE(dropped.find("\"code\""), std::string::npos) << dropped;
  curl(dir, base + "/v1/jobs/" + slow + "/cancel", {"-X", "POST"});
  curl(dir, base + "/v1/jobs/" + queued + "/cancel", {"-X", "POST"});
}

// 8. Silent nonsense: what cannot give a mesh is refused with its reason, or ends FAILED
// saying why, never SUCCEEDED with an empty mesh.
TEST(RestHostile, NonsenseIsRefusedOrFailsSayingWhy) {
  const std::string dir = make_temp_dir("mesh4d-rest-nonsense");
  RunningServer server(dir + "/data");
  const std::string base = rest_base(server);
  const std::string sphere = write_ball(dir + "/sphere.nii", 16, 6);
  std::string bytes;
  {
    std::ifstream in(sphere, std::ios::binary);
    bytes.assign(std::istreambuf_iterator<char>(in), {});
  }
  // A voxel size of NaN, 0 or a negative time step: ITK alone reads them as 1, 1 and 2.
  const std::pair<int, float> bad_spacings[] = {
      {0, std::numeric_limits<float>::quiet_NaN()}, {1, 0.0f}, {3, -2.0f}};
  for (const auto& [axis, value] : bad_spacings) {
    std::string patched = bytes;
    std::memcpy(&patched[80 + 4 * axis], &value, 4);
    const std::string file = dir + "/spacing" + std::to_string(axis) + ".nii";
    std::ofstream(file, std::ios::binary) << patched;
    const Http h = curl(dir, base + "/v1/jobs?delta=3", {"--data-binary", "@" + file});
    EXPECT_EQ(h.status, 400) << h.body;
    EXPECT_NE(h.body.find("pixdim[" + std::to_string(axis + 1) + "]"), std::string::npos) << h.body;
  }
  const Http order =
      curl(dir, base + "/v1/jobs?delta=3&rule_order=99", {"--data-binary", "@" + sphere});
  EXPECT_EQ(order.status, 400) << order.body;
  // Accepted, but no mesh can come of them: FAILED, with the reason. A δ far over the object
  // (REST), one voxel, and one frame (gRPC: a NIfTI file drops a single frame's axis), which
  // may give a mesh but never an empty one.
  const Http huge = curl(dir, base + "/v1/jobs?delta=1e12", {"--data-binary", "@" + sphere});
  ASSERT_EQ(huge.status, 201) << huge.body;
  std::vector<std::string> ids{huge.json()["job"]["id"]};
  auto stub = server.stub();
  domain::LabelImage4 dot({1, 1, 1, 1}, {1, 1, 1, 1});
  dot.set(0, 1);
  const auto ball = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 6);
  domain::LabelImage4 frame({16, 16, 16, 1}, {1, 1, 1, 1});
  for (std::size_t i = 0; i < frame.voxel_count(); ++i) frame.set(i, ball.at(i + 8 * 16 * 16 * 16));
  for (const auto* image : {&dot, &frame}) {
    const Upload up = make_upload(*image, 3, "");
    v1::SubmitJobResponse response;
    ASSERT_TRUE(submit(*stub, up.spec, up.data, &response).ok());
    ids.push_back(response.job().id());
  }
  const char* reasons[] = {"the mesh is empty", "no surface to mesh", ""};
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const v1::Job job = wait_until_done(*stub, ids[k]);
    SCOPED_TRACE(job.ShortDebugString());
    if (k == 2 && job.state() == v1::JOB_STATE_SUCCEEDED) {
      // One frame, closed half a frame before and after: a thin slab, meshed.
      EXPECT_GT(job.stats().pentatopes(), 0u);
      continue;
    }
    EXPECT_EQ(job.state(), v1::JOB_STATE_FAILED);
    EXPECT_NE(job.error().find(reasons[k]), std::string::npos) << job.error();
  }
}

// 7. Shutdown: an idle server (every face open) exits within a second of SIGTERM (3.4 s
// before); a busy one starts no queued job after the signal, ends its event streams, exits
// within 3 s, and has both jobs waiting at the restart.
TEST(RestHostile, SigtermStopsPromptlyAndStartsNothingNew) {
  const std::string dir = make_temp_dir("mesh4d-rest-sigterm");
  {
    RunningServer idle(dir + "/idle");
    EXPECT_EQ(idle.process().stop(SIGTERM, std::chrono::milliseconds(1000)), 0)
        << "not out within 1 s";
  }
  std::string slow, queued;
  {
    RunningServer server(dir + "/data", {"--running-jobs", "1"});
    const std::string base = rest_base(server);
    const std::string sphere = write_ball(dir + "/sphere.nii.gz", 24, 8);
    slow = curl(dir, base + "/v1/jobs?delta=1.2&threads=1&vertex_budget=400000",
                {"--data-binary", "@" + sphere})
               .json()["job"]["id"];
    queued =
        curl(dir, base + "/v1/jobs?delta=3", {"--data-binary", "@" + sphere}).json()["job"]["id"];
    for (int k = 0;
         k < 100 && curl(dir, base + "/v1/jobs/" + slow).json()["state"] != "JOB_STATE_RUNNING";
         ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    // An event stream open on the queued job must not hold the shutdown up either.
    RawConnection stream(server.http_port(),
                         "GET /v1/jobs/" + queued + "/events HTTP/1.1\r\nHost: a\r\n\r\n");
    EXPECT_EQ(stream.read_some(5000).rfind("HTTP/1.1 200", 0), 0u);
    // A kept-alive connection (the stream's, once it ended) holds civetweb's worker for up to
    // the keep-alive timeout (1 s).
    EXPECT_EQ(server.process().stop(SIGTERM, std::chrono::milliseconds(3000)), 0)
        << "not out within 3 s";
  }
  // The first run's log: the queued job never ran; the running one was interrupted.
  std::stringstream log;
  log << std::ifstream(dir + "/data.log").rdbuf();
  std::size_t queued_ran = 0, interrupted = 0;
  for (std::string line; std::getline(log, line);) {
    queued_ran += line.find(queued) != std::string::npos &&
                  line.find("\"msg\":\"running\"") != std::string::npos;
    interrupted += line.find(slow) != std::string::npos &&
                   line.find("interrupted by shutdown") != std::string::npos;
  }
  EXPECT_EQ(queued_ran, 0u) << log.str();
  EXPECT_EQ(interrupted, 1u) << log.str();
  RunningServer restarted(dir + "/data");
  auto stub = restarted.stub();
  for (const auto& id : {slow, queued}) {
    grpc::ClientContext context;
    v1::GetJobRequest request;
    request.set_job_id(id);
    v1::Job job;
    ASSERT_TRUE(stub->GetJob(&context, request, &job).ok());
    EXPECT_TRUE(job.state() == v1::JOB_STATE_QUEUED || job.state() == v1::JOB_STATE_RUNNING)
        << job.ShortDebugString();
  }
}

// The ids of an event stream's messages ("id: N" lines), to its end.
std::vector<std::uint64_t> event_ids(const Http& h) {
  std::vector<std::uint64_t> ids;
  std::istringstream in(h.body);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("id: ", 0) == 0) ids.push_back(std::stoull(line.substr(4)));
  return ids;
}

// 6. Time and order: timestamps and durations below the second, the listing in creation order
// across a restart, and event numbers that never repeat after one.
TEST(RestHostile, TimesOrderAndEventNumbersSurviveARestart) {
  const std::string dir = make_temp_dir("mesh4d-rest-order");
  const std::string sphere = write_ball(dir + "/sphere.nii.gz", 16, 6);
  std::vector<std::string> ids;
  std::uint64_t last_seen = 0;
  {
    RunningServer server(dir + "/data", {"--running-jobs", "1"});
    const std::string base = rest_base(server);
    for (int k = 0; k < 4; ++k)  // within a second
      ids.push_back(curl(dir, base + "/v1/jobs?delta=3&name=n" + std::to_string(k),
                         {"--data-binary", "@" + sphere})
                        .json()["job"]["id"]);
    for (const auto& id : ids) {
      const auto seen = event_ids(curl(dir, base + "/v1/jobs/" + id + "/events"));
      ASSERT_FALSE(seen.empty());
      for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_EQ(seen[k], seen[k - 1] + 1);
      if (id == ids[0]) last_seen = seen.back();
    }
    // Durations of a fraction of a second are summed as such.
    const Http metrics =
        curl(dir, "http://127.0.0.1:" + std::to_string(server.metrics_port()) + "/metrics");
    const std::string name = "\nmesh4d_job_duration_seconds_sum ";
    const auto at = metrics.body.find(name);
    ASSERT_NE(at, std::string::npos) << metrics.body;
    const double sum = std::stod(metrics.body.substr(at + name.size()));
    EXPECT_GT(sum, 0.0);
    EXPECT_NE(sum, std::floor(sum)) << "whole seconds";
    const auto job = curl(dir, base + "/v1/jobs/" + ids[0]).json();
    EXPECT_NE(job["created"].get<std::string>().find('.'), std::string::npos) << job.dump();
    ASSERT_EQ(server.process().stop(SIGTERM), 0);
  }
  RunningServer server(dir + "/data");
  const std::string base = rest_base(server);
  std::vector<std::string> listed;
  const Http list = curl(dir, base + "/v1/jobs");
  const nlohmann::json page = list.json();
  for (const auto& job : page["jobs"]) listed.push_back(job["id"]);
  EXPECT_EQ(listed, ids) << "listed in creation order: " << list.status << " " << list.body;
  const auto after = event_ids(curl(dir, base + "/v1/jobs/" + ids[0] + "/events"));
  ASSERT_FALSE(after.empty());
  EXPECT_GT(after.front(), last_seen) << "an event number seen before the restart came again";
}

// 8. Error messages name no path on the server: a store that cannot write (its jobs folder
// replaced by a file) is INTERNAL, with the data directory as <data-dir>.
TEST(RestHostile, StoreErrorsNameNoServerPath) {
  const std::string dir = make_temp_dir("mesh4d-rest-paths");
  RunningServer server(dir + "/data");
  const std::string base = rest_base(server);
  const std::string sphere = write_ball(dir + "/sphere.nii.gz", 16, 6);
  std::filesystem::remove_all(dir + "/data/jobs");
  std::ofstream(dir + "/data/jobs") << "not a folder";
  const Http h = curl(dir, base + "/v1/jobs?delta=3", {"--data-binary", "@" + sphere});
  EXPECT_EQ(h.status, 500) << h.body;
  EXPECT_EQ(h.json()["code"], "INTERNAL") << h.body;
  EXPECT_EQ(h.body.find(dir), std::string::npos) << h.body;
  EXPECT_NE(h.body.find("<data-dir>"), std::string::npos) << h.body;
  EXPECT_EQ(curl(dir, base + "/v1/jobs").status, 200) << "still serving";
}

// 8. A multipart boundary of one character (RFC 2046 allows 1 to 70; civetweb's parser wanted 4).
TEST(RestHostile, AOneCharacterMultipartBoundaryIsRead) {
  const std::string dir = make_temp_dir("mesh4d-rest-boundary");
  RunningServer server(dir + "/data");
  const std::string base = rest_base(server);
  const std::string sphere = write_ball(dir + "/sphere.nii.gz", 16, 6);
  std::ifstream in(sphere, std::ios::binary);
  const std::string image((std::istreambuf_iterator<char>(in)), {});
  std::ofstream(dir + "/form.bin", std::ios::binary)
      << "--x\r\nContent-Disposition: form-data; name=\"image\"; filename=\"s.nii.gz\"\r\n\r\n"
      << image << "\r\n--x\r\nContent-Disposition: form-data; name=\"params\"\r\n\r\n"
      << "{\"delta\": 3}\r\n--x--\r\n";
  const Http h = curl(dir, base + "/v1/jobs",
                      {"-H", "Content-Type: multipart/form-data; boundary=x", "--data-binary",
                       "@" + dir + "/form.bin"});
  EXPECT_EQ(h.status, 201) << h.body;
  EXPECT_EQ(h.json()["job"]["params"]["delta"], 3) << h.body;
}

// 5. Keep-alive: two requests on one connection both get answers (curl reuses it).
TEST(RestHostile, TwoRequestsOnOneConnection) {
  const std::string dir = make_temp_dir("mesh4d-rest-keepalive");
  RunningServer server(dir + "/data");
  const std::string url = "http://127.0.0.1:" + std::to_string(server.http_port()) + "/v1/jobs";
  const RunResult r = run_command({"/usr/bin/curl", "-sS", "-v", "-o", "/dev/null", "-o",
                                   "/dev/null", "-w", "%{http_code}\n", url, url});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("200\n200\n"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("Re-using existing connection"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace mesh4d::testing
