// The job service end to end: the real mesh4d-server on a loopback port, driven through gRPC
// and through the real mesh4d-client; results read back with the engine's reader and checked.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <thread>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "domain/time_scale.h"
#include "mesh/mesh_check.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_slice.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

domain::LabelImage4 small_sphere() {
  return domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
}

// Fidelity of a fetched mesh: boundary vertices on ∂Ω of the image at the job's time scale, on
// a time cap (half a frame past an end frame), or off ∂Ω by no more than the job's sag offset
// (`offset`, its stats' boundary_offset); every region closed and manifold.
void expect_fidelity(const mesh::Mesh4& m, domain::LabelImage4 image, double time_scale,
                     double offset) {
  ASSERT_GT(m.pentatopes.size(), 100u);
  image.set_time_spacing(time_scale);
  const domain::SurfaceOracle oracle(image);
  const double caps[2] = {image.voxel_center(0, 0, 0, 0)[3] - time_scale / 2,
                          image.voxel_center(0, 0, 0, image.dims()[3] - 1)[3] + time_scale / 2};
  for (const auto& b : m.boundary)
    for (auto v : b.vertices) {
      const double t = m.vertices[v][3];
      if (std::abs(t - caps[0]) < 1e-6 || std::abs(t - caps[1]) < 1e-6) continue;
      if (std::abs(oracle.cut_value(m.vertices[v], 1, 0)) <= 1e-6) continue;
      const domain::SurfacePoint z = oracle.closest_surface_point(m.vertices[v]);
      ASSERT_NE(z.inner, z.outer) << "vertex " << v;
      ASSERT_LE(distance(z.point, m.vertices[v]), offset * (1 + 1e-6) + 1e-9) << "vertex " << v;
    }
  const auto check = mesh::check_boundary(m);
  EXPECT_EQ(check.non_feature_uses, 0u);
  EXPECT_EQ(check.odd, 0u);
  EXPECT_EQ(check.pinched, 0u);
}

// Every job carries its fidelity certificate, one entry per label; a defect is a warning, and
// with strict it fails the job instead, the certificate kept with it.
TEST(JobService, EveryJobCarriesItsCertificateAndStrictFailsOnADefect) {
  const std::string dir = make_temp_dir("mesh4d-certificate");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  auto stub = server.stub();
  const auto run = [&](const domain::LabelImage4& image, double delta, bool strict,
                       const std::string& request_id) {
    Upload u = make_upload(image, delta, request_id);
    u.spec.mutable_params()->set_strict(strict);
    v1::SubmitJobResponse submitted;
    EXPECT_TRUE(submit(*stub, u.spec, u.data, &submitted).ok());
    return wait_until_done(*stub, submitted.job().id());
  };
  const auto defects = [](const v1::Job& job) {
    std::size_t n = 0;
    for (const auto& c : job.stats().certificate())
      n += c.touching_pieces() > 0 || c.mesh_pieces() != c.image_pieces() ||
           c.non_manifold_vertices() > 0 || c.non_manifold_edges() > 0 ||
           c.non_manifold_triangles() > 0;
    return n;
  };
  const auto warned = [](const v1::Job& job) {
    std::size_t n = 0;
    for (const auto& w : job.warnings()) n += w.rfind("fidelity certificate: label ", 0) == 0;
    return n;
  };
  const auto ventricle = domain::beating_ventricle_phantom({40, 40, 16, 6}, {4.4, 4.4, 16, 3});
  const v1::Job lenient = run(ventricle, 8, false, "certificate-1");
  ASSERT_EQ(lenient.state(), v1::JOB_STATE_SUCCEEDED) << lenient.error();
  ASSERT_EQ(lenient.stats().certificate_size(), 2);
  for (const auto& c : lenient.stats().certificate()) {
    EXPECT_GE(c.image_pieces(), 1u);
    EXPECT_GT(c.volume(), 0);
    EXPECT_GT(c.voxel_volume(), 0);
  }
  EXPECT_EQ(warned(lenient), defects(lenient));
  std::printf("the coarse ventricle: %zu of 2 labels with a defect\n", defects(lenient));
  const v1::Job strict = run(ventricle, 8, true, "certificate-2");
  EXPECT_EQ(strict.state(), defects(lenient) > 0 ? v1::JOB_STATE_FAILED : v1::JOB_STATE_SUCCEEDED);
  EXPECT_EQ(strict.stats().certificate_size(), 2) << "the certificate stays with a failed job";
  if (strict.state() == v1::JOB_STATE_FAILED) {
    EXPECT_NE(strict.error().find("strict: the fidelity certificate found defects"),
              std::string::npos)
        << strict.error();
  }
  const v1::Job sphere =
      run(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5), 2, true, "certificate-3");
  EXPECT_EQ(sphere.state(), v1::JOB_STATE_SUCCEEDED) << sphere.error();
  EXPECT_EQ(defects(sphere), 0u);
  EXPECT_TRUE(sphere.params().strict());
}

// The cleanup before meshing: a one-voxel speck of another label is removed by default (the
// job records the threshold used and warns), and kept with min_island_voxels = 0.
TEST(JobService, SmallIslandsAreCleanedByDefaultAndSaidSo) {
  const std::string dir = make_temp_dir("mesh4d-cleanup");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  auto stub = server.stub();
  auto image = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
  image.set(1, 1, 1, 1, 2);
  const auto run = [&](std::optional<unsigned> threshold, const std::string& request_id) {
    Upload u = make_upload(image, 3, request_id);
    if (threshold) u.spec.mutable_params()->set_min_island_voxels(*threshold);
    v1::SubmitJobResponse submitted;
    EXPECT_TRUE(submit(*stub, u.spec, u.data, &submitted).ok());
    return wait_until_done(*stub, submitted.job().id());
  };
  const auto cleanup_warnings = [](const v1::Job& job) {
    std::vector<std::string> out;
    for (const auto& w : job.warnings())
      if (w.rfind("segmentation cleanup: ", 0) == 0) out.push_back(w);
    return out;
  };
  const v1::Job cleaned = run(std::nullopt, "cleanup-1");
  ASSERT_EQ(cleaned.state(), v1::JOB_STATE_SUCCEEDED) << cleaned.error();
  EXPECT_TRUE(cleaned.params().has_min_island_voxels());
  EXPECT_EQ(cleaned.params().min_island_voxels(), domain::kDefaultMinIslandVoxels);
  const auto warnings = cleanup_warnings(cleaned);
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("label 2: 1 islands removed (1 voxels"), std::string::npos)
      << warnings[0];
  EXPECT_EQ(cleaned.stats().certificate_size(), 1) << "label 2 is gone from the image meshed";
  const v1::Job kept = run(0u, "cleanup-2");
  ASSERT_EQ(kept.state(), v1::JOB_STATE_SUCCEEDED) << kept.error();
  EXPECT_EQ(kept.params().min_island_voxels(), 0u);
  EXPECT_TRUE(cleanup_warnings(kept).empty());
}

// A cycle submitted with --time-topology periodic: the job says so, the fetched mesh is closed
// in time (the .m4d's periodic section, glued at the seam) over frames × time scale, its
// certificate finds no defect, and the exports cover the period.
TEST(JobService, APeriodicCycleWithTheRealClient) {
  const std::string dir = make_temp_dir("mesh4d-periodic");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  // A ball that lives across the end of the cycle, beside one that beats.
  const auto image = domain::appearing_ball_phantom({36, 24, 24, 12}, {1, 1, 1, 1}, 10);
  domain::write_nifti(image, dir + "/cycle.nii.gz");
  const RunResult r = run_command(
      {MESH4D_CLIENT_BIN, "--server", server.address(), "submit", dir + "/cycle.nii.gz", "--delta",
       "2", "--time-topology", "periodic", "--wait", "--out", dir + "/cycle.m4d"},
      std::chrono::seconds(120));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(chosen from the data), periodic time"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("warning:"), std::string::npos) << r.output;
  const mesh::Mesh4 m = mesh::read_m4d(dir + "/cycle.m4d");
  ASSERT_TRUE(m.periodic());
  const double time_scale = domain::automatic_time_scale(image, 2, true);
  EXPECT_NEAR(m.period, 12 * time_scale, 1e-6);
  EXPECT_NEAR(m.period_start, -time_scale / 2, 1e-6);
  EXPECT_FALSE(m.periodic_twins.empty());
  const auto check = mesh::check_boundary(m);
  EXPECT_EQ(check.odd, 0u);
  EXPECT_EQ(check.pinched, 0u);
  const std::string id = r.output.substr(0, r.output.find('\n'));
  const RunResult status =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "status", id});
  EXPECT_NE(status.output.find("per frame, periodic time, sag offset on"), std::string::npos)
      << status.output;
  const RunResult exported = run_command({MESH4D_CLIENT_BIN, "export", dir + "/cycle.m4d", "--mfem",
                                          dir + "/cycle.mfem", "--vtu", dir + "/vtu"});
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_NE(exported.output.find("cycle.mfem.v2v (periodic in time"), std::string::npos)
      << exported.output;
  EXPECT_TRUE(std::filesystem::exists(dir + "/cycle.mfem.v2v"));
  // Every whole time unit of the period: frames × time scale of them.
  const std::string slices = "wrote " + std::to_string(static_cast<int>(m.period)) + " slices";
  EXPECT_NE(exported.output.find(slices), std::string::npos) << exported.output;
}

// --sag-offset off: the job records it and reports no vertex moved off ∂Ω; a bad value is refused.
TEST(JobService, TheSagOffsetTurnedOffWithTheRealClient) {
  const std::string dir = make_temp_dir("mesh4d-on-surface");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  domain::write_nifti(small_sphere(), dir + "/sphere.nii.gz");
  const RunResult r = run_command(
      {MESH4D_CLIENT_BIN, "--server", server.address(), "submit", dir + "/sphere.nii.gz", "--delta",
       "3", "--sag-offset", "off", "--wait", "--out", dir + "/out.m4d"},
      std::chrono::seconds(120));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("off the surface by at most 0 (sag offset)"), std::string::npos)
      << r.output;
  const std::string id = r.output.substr(0, r.output.find('\n'));
  const RunResult status =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "status", id});
  EXPECT_NE(status.output.find("open time, sag offset off"), std::string::npos) << status.output;
  const RunResult refused = run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "submit",
                                         dir + "/sphere.nii.gz", "--sag-offset", "maybe"});
  EXPECT_NE(refused.exit_code, 0);
  EXPECT_NE(refused.output.find("--sag-offset"), std::string::npos) << refused.output;
}

TEST(JobService, SubmitWatchFetchWithTheRealClient) {
  const std::string dir = make_temp_dir("mesh4d-jobs");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  const auto image = small_sphere();
  domain::write_nifti(image, dir + "/sphere.nii.gz");

  // The client: submit --wait --out, then the engine's reader.
  const RunResult r =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "submit",
                   dir + "/sphere.nii.gz", "--delta", "3", "--wait", "--out", dir + "/out.m4d"},
                  std::chrono::seconds(120));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("JOB_STATE_SUCCEEDED"), std::string::npos) << r.output;
  // The time scale chosen from the data, as the client prints it.
  const std::string printed = "time scale: ";
  const std::size_t at = r.output.find(printed);
  ASSERT_NE(at, std::string::npos) << r.output;
  EXPECT_NE(r.output.find("per frame (chosen from the data)", at), std::string::npos) << r.output;
  const double time_scale = std::stod(r.output.substr(at + printed.size()));
  EXPECT_DOUBLE_EQ(time_scale, domain::automatic_time_scale(image, 3));
  // How far the sag offset moved a boundary vertex, as the client prints it.
  const std::string off = "boundary vertices off the surface by at most ";
  const std::size_t off_at = r.output.find(off);
  ASSERT_NE(off_at, std::string::npos) << r.output;
  const double offset = std::stod(r.output.substr(off_at + off.size()));
  EXPECT_GT(offset, 0);
  const mesh::Mesh4 m = mesh::read_m4d(dir + "/out.m4d");
  expect_fidelity(m, image, time_scale, offset * (1 + 1e-3));

  // The events, watched from the start of a second job through gRPC: a snapshot first, vertex
  // and rule counts that rise, the statistics, then SUCCEEDED.
  auto stub = server.stub();
  const Upload u = make_upload(image, 2.5, "watch-1");
  v1::SubmitJobResponse submitted;
  ASSERT_TRUE(submit(*stub, u.spec, u.data, &submitted).ok());
  grpc::ClientContext context;
  v1::WatchJobRequest request;
  request.set_job_id(submitted.job().id());
  auto reader = stub->WatchJob(&context, request);
  v1::JobEvent event;
  std::vector<v1::JobEvent> events;
  while (reader->Read(&event)) events.push_back(event);
  ASSERT_TRUE(reader->Finish().ok());
  ASSERT_GE(events.size(), 3u);
  EXPECT_TRUE(events.front().has_snapshot());
  std::uint64_t last_vertices = 0, last_r1 = 0, rises = 0;
  for (const auto& e : events) {
    if (!e.has_progress() || e.progress().phase() != v1::PHASE_REFINING) continue;
    EXPECT_GE(e.progress().vertices(), last_vertices);
    EXPECT_GE(e.progress().insertions().r1(), last_r1);
    rises += e.progress().vertices() > last_vertices;
    last_vertices = e.progress().vertices();
    last_r1 = e.progress().insertions().r1();
  }
  EXPECT_GT(last_vertices, 0u);
  EXPECT_GT(last_r1, 0u);
  for (std::size_t i = 1; i < events.size(); ++i)
    EXPECT_EQ(events[i].sequence(), events[i - 1].sequence() + 1);
  ASSERT_TRUE(events[events.size() - 2].has_finished());
  EXPECT_GT(events[events.size() - 2].finished().pentatopes(), 100u);
  EXPECT_EQ(events.back().state(), v1::JOB_STATE_SUCCEEDED);
  std::printf("%zu events, vertex count rose %llu times to %llu\n", events.size(),
              (unsigned long long)rises, (unsigned long long)last_vertices);

  // A late watcher gets the finished job at once.
  grpc::ClientContext late;
  auto late_reader = stub->WatchJob(&late, request);
  ASSERT_TRUE(late_reader->Read(&event));
  EXPECT_EQ(event.snapshot().state(), v1::JOB_STATE_SUCCEEDED);
  EXPECT_FALSE(late_reader->Read(&event));
  EXPECT_TRUE(late_reader->Finish().ok());

  // The metrics moved: two jobs succeeded, uploads and a download counted, rules counted.
  ASSERT_GT(server.metrics_port(), 0);
  const RunResult scrape =
      run_command({"/usr/bin/curl", "-sS",
                   "http://127.0.0.1:" + std::to_string(server.metrics_port()) + "/metrics"});
  ASSERT_EQ(scrape.exit_code, 0) << scrape.output;
  const std::string& text = scrape.output;
  EXPECT_NE(text.find("mesh4d_jobs_finished_total{state=\"succeeded\"} 2"), std::string::npos)
      << text;
  EXPECT_NE(text.find("mesh4d_jobs{state=\"succeeded\"} 2"), std::string::npos) << text;
  EXPECT_NE(text.find("mesh4d_job_duration_seconds_count 2"), std::string::npos) << text;
  EXPECT_EQ(text.find("mesh4d_received_bytes_total 0"), std::string::npos) << text;
  EXPECT_EQ(text.find("mesh4d_sent_bytes_total 0"), std::string::npos) << text;
  EXPECT_EQ(text.find("mesh4d_insertions_total{rule=\"R1\"} 0"), std::string::npos) << text;
  EXPECT_NE(text.find("mesh4d_insertions_total{rule=\"R1\"}"), std::string::npos) << text;
  EXPECT_EQ(text.find("mesh4d_pentatopes_produced_total 0"), std::string::npos) << text;
}

// --extend-time repeats the end frames before meshing: the first and last frames' volumes,
// read from the 4D mesh's cross-sections, come much closer to the voxels' (measured on this
// phantom: |errors| summed over both labels and both end frames 175 % without, 35 % with).
TEST(JobService, ExtendedTimeKeepsTheEndFramesFaithful) {
  const std::string dir = make_temp_dir("mesh4d-extend");
  RunningServer server(dir + "/data");
  ASSERT_FALSE(server.address().empty());
  const auto image = domain::beating_ventricle_phantom({50, 50, 22, 8}, {3.54, 3.54, 12, 2});
  domain::write_nifti(image, dir + "/ventricle.nii.gz");
  const auto& d = image.dims();
  const auto& s = image.spacing();
  auto end_frame_error = [&](const mesh::Mesh4& m) {
    double sum = 0;
    for (std::size_t t : {std::size_t{0}, d[3] - 1}) {
      double voxels[3] = {0, 0, 0};
      for (std::size_t z = 0; z < d[2]; ++z)
        for (std::size_t y = 0; y < d[1]; ++y)
          for (std::size_t x = 0; x < d[0]; ++x) voxels[image.at(x, y, z, t)] += s[0] * s[1] * s[2];
      const auto v = mesh::slice_volumes(m, image.voxel_center(0, 0, 0, t)[3]);
      for (mesh::Label l : {1, 2})
        sum += std::abs((v.count(l) ? v.at(l) : 0) - voxels[l]) / voxels[l];
    }
    return sum;
  };
  std::vector<mesh::Mesh4> meshes;
  for (const char* frames : {"0", "4"}) {
    const std::string out = dir + "/extend" + frames + ".m4d";
    const RunResult r = run_command(
        {MESH4D_CLIENT_BIN, "--server", server.address(), "submit", dir + "/ventricle.nii.gz",
         "--delta", "8", "--time-scale", "2", "--extend-time", frames, "--wait", "--out", out},
        std::chrono::seconds(120));
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(r.output.find("extend_time_frames") != std::string::npos, frames[0] != '0')
        << r.output;
    EXPECT_NE(r.output.find("time scale: 2 per frame\n"), std::string::npos) << r.output;
    meshes.push_back(mesh::read_m4d(out));
  }
  double earliest = 1e300;
  for (const auto& p : meshes[1].vertices) earliest = std::min(earliest, p[3]);
  EXPECT_LT(earliest, image.voxel_center(0, 0, 0, 0)[3] - 3 * s[3]) << "the mesh spans more time";
  const double without = end_frame_error(meshes[0]), with = end_frame_error(meshes[1]);
  std::printf("end-frame volume errors, summed: %.2f without, %.2f with 4 repeated frames\n",
              without, with);
  EXPECT_LT(with, 0.5 * without);
}

TEST(JobService, KilledServerResumesItsJobAndKeepsEarlierResults) {
  const std::string dir = make_temp_dir("mesh4d-restart");
  const auto image = small_sphere();
  std::string done_id, running_id;
  std::map<std::string, double> time_scale, offset;  // each job's, by id
  {
    RunningServer server(dir + "/data");
    auto stub = server.stub();
    const Upload quick = make_upload(image, 4, "quick");
    v1::SubmitJobResponse a;
    ASSERT_TRUE(submit(*stub, quick.spec, quick.data, &a).ok());
    done_id = a.job().id();
    const v1::Job done = wait_until_done(*stub, done_id);
    ASSERT_EQ(done.state(), v1::JOB_STATE_SUCCEEDED);
    time_scale[done_id] = done.params().time_scale();
    offset[done_id] = done.stats().boundary_offset();
    const Upload slow = make_upload(image, 1.5, "slow");
    v1::SubmitJobResponse b;
    ASSERT_TRUE(submit(*stub, slow.spec, slow.data, &b).ok());
    running_id = b.job().id();
    // Kill -9 once the job is refining.
    v1::Job job;
    for (int i = 0; i < 400 && job.progress().vertices() == 0; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(25));
      grpc::ClientContext c;
      v1::GetJobRequest get;
      get.set_job_id(running_id);
      ASSERT_TRUE(stub->GetJob(&c, get, &job).ok());
    }
    ASSERT_EQ(job.state(), v1::JOB_STATE_RUNNING);
    ASSERT_GT(job.progress().vertices(), 0u);
    server.process().stop(SIGKILL);
  }
  RunningServer restarted(dir + "/data");
  ASSERT_FALSE(restarted.address().empty());
  auto stub = restarted.stub();
  const v1::Job finished = wait_until_done(*stub, running_id);
  EXPECT_EQ(finished.state(), v1::JOB_STATE_SUCCEEDED) << finished.error();
  time_scale[running_id] = finished.params().time_scale();
  offset[running_id] = finished.stats().boundary_offset();
  for (const auto& id : {done_id, running_id}) {
    const RunResult fetch = run_command({MESH4D_CLIENT_BIN, "--server", restarted.address(),
                                         "fetch", id, "--out", dir + "/" + id + ".m4d"});
    ASSERT_EQ(fetch.exit_code, 0) << fetch.output;
    expect_fidelity(mesh::read_m4d(dir + "/" + id + ".m4d"), image, time_scale.at(id),
                    offset.at(id));
  }
  // The same request id after the restart still finds the same job.
  const Upload again = make_upload(image, 1.5, "slow");
  v1::SubmitJobResponse dup;
  ASSERT_TRUE(submit(*stub, again.spec, again.data, &dup).ok());
  EXPECT_TRUE(dup.deduplicated());
  EXPECT_EQ(dup.job().id(), running_id);
}

TEST(JobService, ConcurrentSubmitsAreAcceptedOrRefusedAndNoneIsLost) {
  const std::string dir = make_temp_dir("mesh4d-load");
  RunningServer server(dir + "/data", {"--max-queued-jobs", "4"});
  auto stub = server.stub();
  const auto image = domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5);
  constexpr int kClients = 50;
  std::vector<std::future<std::pair<grpc::Status, v1::SubmitJobResponse>>> calls;
  for (int i = 0; i < kClients; ++i)
    calls.push_back(std::async(std::launch::async, [&, i] {
      const Upload u = make_upload(image, 3, "load-" + std::to_string(i));
      v1::SubmitJobResponse response;
      const grpc::Status s = submit(*stub, u.spec, u.data, &response);
      return std::make_pair(s, response);
    }));
  std::set<std::string> accepted;
  int refused = 0;
  for (int i = 0; i < kClients; ++i) {
    auto [status, response] = calls[i].get();
    if (status.ok()) {
      EXPECT_TRUE(accepted.insert(response.job().id()).second) << "two submits, one job";
      // A retry with the same request id lands on the same job.
      const Upload u = make_upload(image, 3, "load-" + std::to_string(i));
      v1::SubmitJobResponse retry;
      ASSERT_TRUE(submit(*stub, u.spec, u.data, &retry).ok());
      EXPECT_TRUE(retry.deduplicated());
      EXPECT_EQ(retry.job().id(), response.job().id());
    } else {
      EXPECT_EQ(status.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED)
          << status.error_message();
      ++refused;
    }
  }
  std::printf("%zu accepted, %d refused with RESOURCE_EXHAUSTED\n", accepted.size(), refused);
  EXPECT_GT(accepted.size(), 0u);
  EXPECT_GT(refused, 0);
  for (const auto& id : accepted)
    EXPECT_EQ(wait_until_done(*stub, id).state(), v1::JOB_STATE_SUCCEEDED);
  grpc::ClientContext c;
  v1::ListJobsRequest list;
  list.set_page_size(1000);
  v1::ListJobsResponse jobs;
  ASSERT_TRUE(stub->ListJobs(&c, list, &jobs).ok());
  EXPECT_EQ(static_cast<std::size_t>(jobs.jobs_size()), accepted.size());
}

}  // namespace
}  // namespace mesh4d::testing
