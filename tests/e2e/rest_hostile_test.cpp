// The REST face against hostile and careless clients (curl and raw sockets against the real
// server): each attack of the service-hardening list reproduced, and what the server must do.
#include <gtest/gtest.h>
#include <zlib.h>

#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "http_client.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

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

// 1. A gzip bomb: refused from its header at once, in bounded memory, with a JSON error that
// names no server path.
TEST(RestHostile, GzipBombIsRefusedFromItsHeaderInBoundedMemory) {
  const std::string dir = make_temp_dir("mesh4d-rest-bomb");
  RunningServer server(dir + "/data", {"--max-image-mb", "64"});
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
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
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
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

}  // namespace
}  // namespace mesh4d::testing
