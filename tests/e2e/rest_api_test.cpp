// The REST face end to end, driven with curl against the real server: a phantom file submitted
// as a body, its events followed as Server-Sent Events to the end, the mesh downloaded and read
// with the engine's reader, a slice as .vtu; then the HTTP counterpart of every error of the
// gRPC table (bad_input_test.cpp), and the token.
#include <gtest/gtest.h>

#include <csignal>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <thread>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "http_client.h"
#include "mesh/mesh_io.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

// The SSE messages of a stream: (event name, data as JSON).
std::vector<std::pair<std::string, nlohmann::json>> sse(const std::string& text) {
  std::vector<std::pair<std::string, nlohmann::json>> events;
  std::istringstream in(text);
  std::string name, data;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("event: ", 0) == 0) name = line.substr(7);
    if (line.rfind("data: ", 0) == 0) data = line.substr(6);
    if (line.empty() && !name.empty()) {
      events.emplace_back(name, nlohmann::json::parse(data));
      name.clear();
    }
  }
  return events;
}

TEST(RestApi, SubmitFollowEventsDownloadTheMeshAndASlice) {
  const std::string dir = make_temp_dir("mesh4d-rest");
  RunningServer server(dir + "/data");
  ASSERT_GT(server.http_port(), 0);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
  domain::write_nifti(domain::hypersphere_phantom(), dir + "/sphere.nii.gz");

  const Http submitted = curl(dir, base + "/v1/jobs?delta=2&threads=1&name=sphere&request_id=r-1",
                              {"--data-binary", "@" + dir + "/sphere.nii.gz"});
  ASSERT_EQ(submitted.status, 201) << submitted.headers << submitted.body;
  const auto job = submitted.json()["job"];
  const std::string id = job["id"];
  EXPECT_EQ(header(submitted, "Location"), "/v1/jobs/" + id);
  EXPECT_EQ(job["name"], "sphere");
  EXPECT_EQ(job["params"]["delta"], 2.0);

  // The events, from the start, until the stream ends with the job.
  const Http stream = curl(dir, base + "/v1/jobs/" + id + "/events", {}, 300);
  ASSERT_EQ(stream.status, 200) << stream.headers;
  EXPECT_EQ(header(stream, "Content-Type"), "text/event-stream");
  const auto events = sse(stream.body);
  ASSERT_GE(events.size(), 2u) << stream.body;
  EXPECT_EQ(events.front().first, "snapshot");
  std::uint64_t last = 0, progress = 0, previous_sequence = 0;
  for (const auto& [name, data] : events) {
    const std::uint64_t sequence = std::stoull(data["sequence"].get<std::string>());
    if (previous_sequence) {
      EXPECT_EQ(sequence, previous_sequence + 1);
    }
    previous_sequence = sequence;
    if (name != "progress") continue;
    ++progress;
    const std::uint64_t v = std::stoull(data["progress"]["vertices"].get<std::string>());
    EXPECT_GE(v, last);
    last = v;
  }
  EXPECT_EQ(events.back().first, "state");
  EXPECT_EQ(events.back().second["state"], "JOB_STATE_SUCCEEDED");
  std::printf("%zu events, %llu progress reports, %llu vertices at the last\n", events.size(),
              (unsigned long long)progress, (unsigned long long)last);

  // A retry with the same request id: the same job, 200.
  const Http again = curl(dir, base + "/v1/jobs?delta=2&threads=1&request_id=r-1",
                          {"--data-binary", "@" + dir + "/sphere.nii.gz"});
  EXPECT_EQ(again.status, 200);
  EXPECT_EQ(again.json()["job"]["id"], id);
  EXPECT_EQ(again.json()["deduplicated"], true);

  // The same file as a multipart form with a JSON part of parameters.
  const Http form =
      curl(dir, base + "/v1/jobs",
           {"-F", "image=@" + dir + "/sphere.nii.gz", "-F",
            R"(params={"delta": 4, "seed": 9, "rule_order": "paper"})", "-F", "name=as-form"});
  ASSERT_EQ(form.status, 201) << form.body;
  EXPECT_EQ(form.json()["job"]["name"], "as-form");
  EXPECT_EQ(form.json()["job"]["params"]["delta"], 4.0);
  EXPECT_EQ(form.json()["job"]["params"]["seed"], "9");
  EXPECT_EQ(form.json()["job"]["params"]["rule_order"], "RULE_ORDER_PAPER");

  const Http got = curl(dir, base + "/v1/jobs/" + id);
  ASSERT_EQ(got.status, 200);
  EXPECT_EQ(got.json()["state"], "JOB_STATE_SUCCEEDED");
  EXPECT_EQ(got.json()["params"]["sag_offset"], true) << "the record names the default used";
  EXPECT_GT(got.json()["stats"].value("boundary_offset", 0.0), 0.0);

  // Without the sag offset (a query flag): every boundary vertex stays on ∂Ω.
  const Http on_surface = curl(dir, base + "/v1/jobs?delta=2&threads=1&sag_offset=false",
                               {"--data-binary", "@" + dir + "/sphere.nii.gz"});
  ASSERT_EQ(on_surface.status, 201) << on_surface.body;
  const std::string on_surface_id = on_surface.json()["job"]["id"];
  EXPECT_EQ(on_surface.json()["job"]["params"]["sag_offset"], false);
  curl(dir, base + "/v1/jobs/" + on_surface_id + "/events", {}, 300);  // until it ends
  const Http offset_off = curl(dir, base + "/v1/jobs/" + on_surface_id);
  EXPECT_EQ(offset_off.json()["state"], "JOB_STATE_SUCCEEDED");
  EXPECT_EQ(offset_off.json()["stats"].value("boundary_offset", 0.0), 0.0);
  const Http listed = curl(dir, base + "/v1/jobs?state=succeeded");
  ASSERT_EQ(listed.status, 200);
  ASSERT_GE(listed.json()["jobs"].size(), 1u);
  EXPECT_EQ(listed.json()["jobs"][0]["id"], id);

  const Http mesh = curl(dir, base + "/v1/jobs/" + id + "/mesh");
  ASSERT_EQ(mesh.status, 200);
  EXPECT_EQ(header(mesh, "Content-Length"), std::to_string(mesh.body.size()));
  EXPECT_EQ(
      header(mesh, "X-Mesh4d-SHA256"),
      mesh::sha256_hex(reinterpret_cast<const std::uint8_t*>(mesh.body.data()), mesh.body.size()));
  const mesh::Mesh4 m =
      mesh::decode_m4d(reinterpret_cast<const std::uint8_t*>(mesh.body.data()), mesh.body.size());
  EXPECT_EQ(std::to_string(m.pentatopes.size()),
            got.json()["stats"]["pentatopes"].get<std::string>());

  const Http slice = curl(dir, base + "/v1/jobs/" + id + "/slices/15.5.vtu");
  ASSERT_EQ(slice.status, 200) << slice.body;
  EXPECT_EQ(slice.body.rfind("<?xml", 0), 0u);
  EXPECT_NE(slice.body.find("Name=\"radius_edge_ratio\""), std::string::npos);
  EXPECT_EQ(slice.body.find("NumberOfCells=\"0\""), std::string::npos);
  const Http boundary = curl(dir, base + "/v1/jobs/" + id + "/slices/15.5.vtu?boundary=1");
  ASSERT_EQ(boundary.status, 200);
  EXPECT_NE(boundary.body.find("Name=\"inner_label\""), std::string::npos);

  const Http deleted = curl(dir, base + "/v1/jobs/" + id, {"-X", "DELETE"});
  EXPECT_EQ(deleted.status, 204);
  EXPECT_EQ(curl(dir, base + "/v1/jobs/" + id).status, 404);

  const Http page = curl(dir, base + "/");
  EXPECT_EQ(page.status, 200);
  EXPECT_NE(page.body.find("mesh4d jobs"), std::string::npos);
  // The viewer's bundle: gzip as stored for a client that accepts it, inflated for one that
  // does not; the same script either way.
  const Http gz = curl(dir, base + "/viewer.js", {"-H", "Accept-Encoding: gzip"});
  EXPECT_EQ(gz.status, 200);
  EXPECT_EQ(header(gz, "Content-Encoding"), "gzip");
  EXPECT_EQ(gz.body.substr(0, 2), "\x1f\x8b");
  const Http plain = curl(dir, base + "/viewer.js");
  EXPECT_EQ(plain.status, 200);
  EXPECT_EQ(header(plain, "Content-Encoding"), "");
  EXPECT_GT(plain.body.size(), 3 * gz.body.size());
  EXPECT_NE(plain.body.find("M4DS"), std::string::npos) << "the viewer's decoder";
  const Http compressed = curl(dir, base + "/viewer.js", {"--compressed"});
  EXPECT_EQ(compressed.body, plain.body);
}

TEST(RestApi, EveryErrorOfTheGrpcTableHasItsHttpStatus) {
  const std::string dir = make_temp_dir("mesh4d-rest-bad");
  RunningServer server(dir + "/data", {"--max-vertex-budget", "100000", "--max-image-mb", "2",
                                       "--max-queued-jobs", "2"});
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
  const std::string sphere = dir + "/sphere.nii.gz";
  domain::write_nifti(domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 8), sphere);
  domain::write_nifti(domain::beating_ventricle_phantom(), dir + "/ventricle.nii.gz");
  domain::write_nifti(domain::hypersphere_phantom({24, 24, 24, 24}, {1, 1, 1, 1}, 7),
                      dir + "/other.nii.gz");
  domain::write_nifti(domain::LabelImage4({12, 12, 12, 12}, {1, 1, 1, 1}), dir + "/empty.nii.gz");
  {
    std::ifstream in(sphere, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(dir + "/truncated.nii.gz", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
    std::ofstream(dir + "/junk.nii", std::ios::binary) << "this is not an image";
    std::ofstream(dir + "/big.bin", std::ios::binary) << std::string(4 << 20, 'x');
  }
  // A 3D image: right format, wrong dimension (written by nibabel).
  ASSERT_EQ(run_command({"/usr/bin/python3", "-c",
                         "import nibabel as n, numpy as np, sys\n"
                         "n.save(n.Nifti1Image(np.ones((8, 8, 8), np.uint8), np.eye(4)), "
                         "sys.argv[1])",
                         dir + "/three_d.nii"})
                .exit_code,
            0);
  ASSERT_EQ(
      curl(dir, base + "/v1/jobs?request_id=first&delta=3", {"--data-binary", "@" + sphere}).status,
      201);

  struct Case {
    const char* what;
    std::string path;
    std::vector<std::string> args;
    int status;
    const char* code;
    const char* message;
  };
  const auto body = [](const std::string& file) {
    return std::vector<std::string>{"--data-binary", "@" + file};
  };
  const std::vector<Case> cases = {
      {"junk body", "/v1/jobs", body(dir + "/junk.nii"), 400, "INVALID_ARGUMENT", "not a NIfTI"},
      {"no body", "/v1/jobs", {"-X", "POST"}, 400, "INVALID_ARGUMENT", "no body"},
      {"truncated file", "/v1/jobs", body(dir + "/truncated.nii.gz"), 400, "INVALID_ARGUMENT",
       "not a readable label image"},
      {"3D image", "/v1/jobs", body(dir + "/three_d.nii"), 400, "INVALID_ARGUMENT", "4D"},
      {"empty labels", "/v1/jobs", body(dir + "/empty.nii.gz"), 400, "INVALID_ARGUMENT",
       "foreground"},
      {"NaN time scale", "/v1/jobs?time_scale=NaN", body(sphere), 400, "INVALID_ARGUMENT",
       "params.time_scale nan must be finite and > 0"},
      {"negative time scale", "/v1/jobs?time_scale=-5", body(sphere), 400, "INVALID_ARGUMENT",
       "params.time_scale -5 must be finite and > 0"},
      {"negative delta", "/v1/jobs?delta=-2", body(sphere), 400, "INVALID_ARGUMENT", "delta"},
      {"absurd radius-edge bound", "/v1/jobs?radius_edge_bound=0.1", body(sphere), 400,
       "INVALID_ARGUMENT", "radius_edge_bound"},
      {"time extension over 64", "/v1/jobs?extend_time_frames=100", body(sphere), 400,
       "INVALID_ARGUMENT", "extend_time_frames"},
      {"unknown time topology", "/v1/jobs?time_topology=circular", body(sphere), 400,
       "INVALID_ARGUMENT", "time_topology 'circular' is not one of open, periodic"},
      {"periodic time extended", "/v1/jobs?time_topology=periodic&extend_time_frames=2",
       body(sphere), 400, "INVALID_ARGUMENT", "a periodic one (time_topology periodic) has none"},
      {"unknown parameter", "/v1/jobs?deltaa=3", body(sphere), 400, "INVALID_ARGUMENT", "deltaa"},
      {"unknown rule order", "/v1/jobs?rule_order=fastest", body(sphere), 400, "INVALID_ARGUMENT",
       "rule_order 'fastest' is not one of r3_first, paper"},
      {"unknown format", "/v1/jobs?format=png", body(sphere), 400, "INVALID_ARGUMENT", "png"},
      {"params not an object",
       "/v1/jobs",
       {"-F", "image=@" + sphere, "-F", "params=[1]"},
       400,
       "INVALID_ARGUMENT",
       "JSON object"},
      {"form without an image",
       "/v1/jobs",
       {"-F", "name=x"},
       400,
       "INVALID_ARGUMENT",
       "\"image\" part"},
      {"vertex budget over the limit", "/v1/jobs?vertex_budget=200000", body(sphere), 429,
       "RESOURCE_EXHAUSTED", "vertex_budget"},
      {"image over the limit", "/v1/jobs", body(dir + "/ventricle.nii.gz"), 429,
       "RESOURCE_EXHAUSTED", "at most"},
      {"body over the limit", "/v1/jobs", body(dir + "/big.bin"), 429, "RESOURCE_EXHAUSTED",
       "limit"},
      {"request id reused for another image", "/v1/jobs?request_id=first",
       body(dir + "/other.nii.gz"), 409, "ALREADY_EXISTS", "already used"},
      {"request id reused with other parameters", "/v1/jobs?request_id=first&delta=4", body(sphere),
       409, "ALREADY_EXISTS", "different parameters"},
      {"unknown job", "/v1/jobs/no-such-job", {}, 404, "NOT_FOUND", "no-such-job"},
      {"delete unknown job", "/v1/jobs/no-such-job", {"-X", "DELETE"}, 404, "NOT_FOUND", "no job"},
      {"cancel unknown job",
       "/v1/jobs/no-such-job/cancel",
       {"-X", "POST"},
       404,
       "NOT_FOUND",
       "no job"},
      {"events of unknown job", "/v1/jobs/no-such-job/events", {}, 404, "NOT_FOUND", "no job"},
      {"mesh of unknown job", "/v1/jobs/no-such-job/mesh", {}, 404, "NOT_FOUND", "no job"},
      {"slice of unknown job", "/v1/jobs/no-such-job/slices/1.vtu", {}, 404, "NOT_FOUND", "no job"},
      {"slice not named by a time",
       "/v1/jobs/x/slices/abc.vtu",
       {},
       400,
       "INVALID_ARGUMENT",
       "abc"},
      {"bad page token", "/v1/jobs?page_token=garbage", {}, 400, "INVALID_ARGUMENT", "page"},
      {"unknown state", "/v1/jobs?state=sleeping", {}, 400, "INVALID_ARGUMENT", "sleeping"},
      {"unknown path", "/v2/things", {}, 404, "NOT_FOUND", "/v2/things"},
      {"wrong method", "/v1/jobs/x/mesh", {"-X", "DELETE"}, 405, "UNIMPLEMENTED", "GET"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.what);
    const Http h = curl(dir, base + c.path, c.args);
    EXPECT_EQ(h.status, c.status) << h.headers << h.body;
    const auto j = h.json();
    ASSERT_TRUE(j.is_object()) << h.body;
    EXPECT_EQ(j["code"], c.code) << h.body;
    EXPECT_NE(j["message"].get<std::string>().find(c.message), std::string::npos) << h.body;
  }

  // A slow job: its mesh before it ends (FAILED_PRECONDITION), a full queue (429), cancelled
  // (then its mesh is CANCELLED, 499), a running job cannot be deleted.
  domain::write_nifti(domain::hypersphere_phantom(), dir + "/slow.nii.gz");
  const Http slow = curl(dir, base + "/v1/jobs?delta=1.2&threads=1&vertex_budget=100000",
                         {"--data-binary", "@" + dir + "/slow.nii.gz"});
  ASSERT_EQ(slow.status, 201) << slow.body;
  const std::string id = slow.json()["job"]["id"];
  const Http early = curl(dir, base + "/v1/jobs/" + id + "/mesh");
  EXPECT_EQ(early.status, 400) << early.body;
  EXPECT_EQ(early.json()["code"], "FAILED_PRECONDITION");
  const Http early_delete = curl(dir, base + "/v1/jobs/" + id, {"-X", "DELETE"});
  EXPECT_EQ(early_delete.status, 400) << early_delete.body;
  EXPECT_EQ(early_delete.json()["code"], "FAILED_PRECONDITION");
  int refused = 0;
  for (int k = 0; k < 4; ++k)
    refused += curl(dir, base + "/v1/jobs?delta=3", {"--data-binary", "@" + sphere}).status == 429;
  EXPECT_GE(refused, 1) << "a queue of 2 refuses some of 4 more jobs";
  const Http cancelled = curl(dir, base + "/v1/jobs/" + id + "/cancel", {"-X", "POST"});
  ASSERT_EQ(cancelled.status, 200) << cancelled.body;
  for (int k = 0;
       k < 100 && curl(dir, base + "/v1/jobs/" + id).json()["state"] != "JOB_STATE_CANCELLED"; ++k)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const Http after = curl(dir, base + "/v1/jobs/" + id + "/mesh");
  EXPECT_EQ(after.status, 499) << after.body;
  EXPECT_EQ(after.json()["code"], "CANCELLED");

  // The server is still serving after all of it.
  EXPECT_EQ(curl(dir, base + "/v1/jobs").status, 200);
}

TEST(RestApi, TokenIsRequiredWhenConfigured) {
  const std::string dir = make_temp_dir("mesh4d-rest-token");
  RunningServer server(dir + "/data", {"--token", "s3cret"});
  const std::string base = "http://127.0.0.1:" + std::to_string(server.http_port());
  const Http none = curl(dir, base + "/v1/jobs");
  EXPECT_EQ(none.status, 401);
  EXPECT_EQ(none.json()["code"], "UNAUTHENTICATED");
  const Http wrong = curl(dir, base + "/v1/jobs", {"-H", "Authorization: Bearer nope"});
  EXPECT_EQ(wrong.status, 403);
  EXPECT_EQ(wrong.json()["code"], "PERMISSION_DENIED");
  EXPECT_EQ(curl(dir, base + "/v1/jobs", {"-H", "Authorization: Bearer s3cret"}).status, 200);
  // The scheme is case-insensitive (RFC 7235); the token is not.
  EXPECT_EQ(curl(dir, base + "/v1/jobs", {"-H", "Authorization: bearer s3cret"}).status, 200);
  EXPECT_EQ(curl(dir, base + "/v1/jobs", {"-H", "Authorization: BEARER s3cret"}).status, 200);
  EXPECT_EQ(curl(dir, base + "/v1/jobs", {"-H", "Authorization: bearer S3CRET"}).status, 403);
  EXPECT_EQ(curl(dir, base + "/v1/jobs?access_token=s3cret").status, 200);
  EXPECT_EQ(curl(dir, base + "/").status, 200) << "the page itself is public; its calls are not";
}

}  // namespace
}  // namespace mesh4d::testing
