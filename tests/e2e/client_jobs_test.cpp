// Every job subcommand of the real client on real jobs of the real server: submit (without
// --wait), list, status, watch, cancel, fetch, delete, health; then each of them with the
// server gone (exit 3). Their unknown-id and bad-argument failures are in bad_input_test.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "mesh/mesh_io.h"
#include "server_fixture.h"
#include "wire/digest.h"

namespace mesh4d::testing {
namespace {

// The first line of the client's output: the job id that submit prints.
std::string first_line(const std::string& s) {
  return s.substr(0, s.find('\n'));
}

TEST(ClientJobs, EachSubcommandOnRealJobsThenWithoutAServer) {
  const std::string dir = make_temp_dir("mesh4d-client-jobs");
  RunningServer server(dir + "/data");
  const std::string a = server.address();
  const auto client = [&](std::vector<std::string> args, int seconds = 60) {
    args.insert(args.begin(), {MESH4D_CLIENT_BIN, "--server", a});
    return run_command(args, std::chrono::seconds(seconds));
  };
  domain::write_nifti(domain::beating_ventricle_phantom(), dir + "/ventricle.nii.gz");
  domain::write_nifti(domain::hypersphere_phantom(), dir + "/sphere.nii.gz");

  // A long job (one thread, fine delta), cancelled while it runs.
  const RunResult long_job = client({"submit", dir + "/ventricle.nii.gz", "--delta", "2",
                                     "--threads", "1", "--name", "long-one"});
  ASSERT_EQ(long_job.exit_code, 0) << long_job.output;
  const std::string long_id = first_line(long_job.output);
  ASSERT_FALSE(long_id.empty());
  const RunResult listed = client({"list"});
  ASSERT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_NE(listed.output.find(long_id), std::string::npos) << listed.output;
  EXPECT_NE(listed.output.find("long-one"), std::string::npos) << listed.output;
  const RunResult status = client({"status", long_id});
  ASSERT_EQ(status.exit_code, 0) << status.output;
  EXPECT_TRUE(status.output.find("RUNNING") != std::string::npos ||
              status.output.find("QUEUED") != std::string::npos)
      << status.output;
  const RunResult cancelled = client({"cancel", long_id});
  ASSERT_EQ(cancelled.exit_code, 0) << cancelled.output;
  const RunResult watched_cancelled = client({"watch", long_id});
  EXPECT_EQ(watched_cancelled.exit_code, 5) << watched_cancelled.output;
  EXPECT_NE(watched_cancelled.output.find("CANCELLED"), std::string::npos)
      << watched_cancelled.output;
  const RunResult listed_cancelled = client({"list", "--state", "cancelled"});
  EXPECT_NE(listed_cancelled.output.find(long_id), std::string::npos) << listed_cancelled.output;

  // A short job: watched to its end, its table, fetched, deleted.
  const RunResult short_job = client({"submit", dir + "/sphere.nii.gz", "--delta", "3"});
  ASSERT_EQ(short_job.exit_code, 0) << short_job.output;
  const std::string id = first_line(short_job.output);
  const RunResult watched = client({"watch", id}, 120);
  ASSERT_EQ(watched.exit_code, 0) << watched.output;
  EXPECT_NE(watched.output.find("JOB_STATE_SUCCEEDED"), std::string::npos) << watched.output;
  const RunResult done = client({"status", id});
  ASSERT_EQ(done.exit_code, 0) << done.output;
  EXPECT_NE(done.output.find("SUCCEEDED"), std::string::npos) << done.output;
  EXPECT_NE(done.output.find("radius-edge ratio"), std::string::npos) << done.output;
  // The time scale the job chose, as submit printed it.
  const std::string scale_printed = "time scale: ";
  const std::size_t at = short_job.output.find(scale_printed);
  ASSERT_NE(at, std::string::npos) << short_job.output;
  const std::string scale = short_job.output.substr(
      at + scale_printed.size(),
      short_job.output.find(' ', at + scale_printed.size()) - at - scale_printed.size());
  EXPECT_NE(
      done.output.find("  delta 3, time scale " + scale + " per frame, open time, sag offset on\n"),
      std::string::npos)
      << done.output;
  EXPECT_EQ(client({"list", "--state", "succeeded"}).output.find(long_id), std::string::npos);
  const RunResult fetched = client({"fetch", id, "--out", dir + "/sphere.m4d"});
  ASSERT_EQ(fetched.exit_code, 0) << fetched.output;
  EXPECT_GT(mesh::read_m4d(dir + "/sphere.m4d").pentatopes.size(), 100u);
  // The report beside it: the mesh's checksum and the fidelity certificate, per label.
  std::ifstream report_file(dir + "/sphere.m4d.report.json");
  const auto report = nlohmann::json::parse(report_file, nullptr, false);
  ASSERT_TRUE(report.is_object()) << "no sphere.m4d.report.json";
  std::ifstream mesh_file(dir + "/sphere.m4d", std::ios::binary);
  const std::string mesh_bytes{std::istreambuf_iterator<char>(mesh_file), {}};
  EXPECT_EQ(report["sha256"], wire::sha256_hex(mesh_bytes));
  ASSERT_EQ(report["stats"]["certificate"].size(), 1u) << report.dump();
  EXPECT_EQ(report["stats"]["certificate"][0]["mesh_pieces"], "1");
  EXPECT_GT(report["stats"]["certificate"][0]["image_to_mesh_max"].get<double>(), 0.0);
  const RunResult deleted = client({"delete", id});
  ASSERT_EQ(deleted.exit_code, 0) << deleted.output;
  EXPECT_EQ(client({"status", id}).exit_code, 4);
  EXPECT_EQ(client({"list"}).output.find(id + " "), std::string::npos);

  // No server: every subcommand that calls it says so, exit 3.
  ASSERT_EQ(server.process().stop(SIGTERM), 0);
  const std::vector<std::vector<std::string>> calls = {{"health"},
                                                       {"list"},
                                                       {"status", long_id},
                                                       {"watch", long_id},
                                                       {"cancel", long_id},
                                                       {"delete", long_id},
                                                       {"fetch", long_id, "--out", dir + "/x.m4d"},
                                                       {"submit", dir + "/sphere.nii.gz"}};
  for (auto args : calls) {
    args.insert(args.begin(), "2");
    args.insert(args.begin(), "--timeout");
    const RunResult r = client(args);
    SCOPED_TRACE(args[2]);
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_NE(r.output.find("mesh4d-client:"), std::string::npos) << r.output;
  }
}

// submit's ways to say what to mesh: a series of 3D frames, a JSON parameter file, flags.
TEST(ClientJobs, SubmitTakesFramesParameterFilesAndFlags) {
  const std::string dir = make_temp_dir("mesh4d-client-submit");
  RunningServer server(dir + "/data");
  const auto client = [&](std::vector<std::string> args) {
    args.insert(args.begin(), {MESH4D_CLIENT_BIN, "--server", server.address()});
    return run_command(args, std::chrono::seconds(120));
  };
  domain::write_nifti(domain::hypersphere_phantom({24, 24, 24, 6}, {1, 1, 1, 4}, 9),
                      dir + "/sphere.nii.gz");
  // Its six frames as 3D files, split by nibabel (a foreign writer).
  const RunResult split =
      run_command({"/usr/bin/python3", "-c",
                   "import nibabel as n, sys\n"
                   "im = n.load(sys.argv[1])\n"
                   "for k in range(im.shape[3]):\n"
                   "    n.save(n.Nifti1Image(im.get_fdata()[..., k].astype('uint8'), im.affine), "
                   "sys.argv[2] + '/frame%d.nii' % k)\n",
                   dir + "/sphere.nii.gz", dir});
  ASSERT_EQ(split.exit_code, 0) << split.output;
  std::vector<std::string> frames_args{"submit", "--frames"};
  for (int k = 0; k < 6; ++k) frames_args.push_back(dir + "/frame" + std::to_string(k) + ".nii");
  for (const char* a : {"--time-scale", "4", "--delta", "3", "--wait", "--out"})
    frames_args.push_back(a);
  frames_args.push_back(dir + "/frames.m4d");
  const RunResult frames = client(frames_args);
  ASSERT_EQ(frames.exit_code, 0) << frames.output;
  const mesh::Mesh4 m = mesh::read_m4d(dir + "/frames.m4d");
  double t_max = 0;
  for (const auto& p : m.vertices) t_max = std::max(t_max, p[3]);
  EXPECT_GT(t_max, 4 * 4.0) << "frames four time units apart: the mesh spans them";

  {
    std::ofstream(dir + "/good.json") << R"({"delta": 3, "seed": 7, "rule_order": "paper",
                                            "radius_edge_bound": 1.8})";
    const RunResult r = client({"submit", dir + "/sphere.nii.gz", "--params", dir + "/good.json",
                                "--wait", "--out", dir + "/params.m4d"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const RunResult stats =
        run_command({MESH4D_CLIENT_BIN, "stats", dir + "/params.m4d", "--json"});
    ASSERT_EQ(stats.exit_code, 0) << stats.output;
    const double rho_max = nlohmann::json::parse(stats.output)["radius_edge_ratio"]["max"];
    EXPECT_LT(rho_max, 1.8) << "the file's radius-edge bound";
    EXPECT_GT(rho_max, 1.5) << "and not the default 2 either";
  }
  std::ofstream(dir + "/bad.json") << R"({"deltaa": 3})";
  const RunResult bad = client({"submit", dir + "/sphere.nii.gz", "--params", dir + "/bad.json"});
  EXPECT_EQ(bad.exit_code, 6) << bad.output;
  EXPECT_NE(bad.output.find("unknown parameter 'deltaa'"), std::string::npos) << bad.output;
  // An unknown rule order is refused as the REST face refuses it, not taken as R3 first.
  std::ofstream(dir + "/order.json") << R"({"rule_order": "fastest"})";
  const RunResult order =
      client({"submit", dir + "/sphere.nii.gz", "--params", dir + "/order.json"});
  EXPECT_EQ(order.exit_code, 6) << order.output;
  EXPECT_NE(order.output.find("rule_order 'fastest' is not one of r3_first, paper"),
            std::string::npos)
      << order.output;
  const RunResult rho = client({"submit", dir + "/sphere.nii.gz", "--rho", "0.1"});
  EXPECT_EQ(rho.exit_code, 4) << rho.output;
  EXPECT_NE(rho.output.find("radius_edge_bound = 0.1 is out of range"), std::string::npos)
      << rho.output;
}

}  // namespace
}  // namespace mesh4d::testing
