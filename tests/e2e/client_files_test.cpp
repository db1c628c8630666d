// The client's work on meshes end to end: the real server meshes an image, the real client
// fetches it and exports time slices, MFEM and libMeshb files and the quality table; VTK's own
// reader (Debian's python3-vtk9, tests/python/check_vtu_slices.py) measures every slice against
// the voxels of the matching frame. Also: the failure paths of export and stats, and the
// progress display in a pseudo-terminal and without one.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "mesh/mesh_io.h"
#include "server_fixture.h"

namespace mesh4d::testing {
namespace {

namespace fs = std::filesystem;

// Frame times t = k·scale, k = 0..frames-1, for --slices.
std::string frame_times(int frames, double scale) {
  std::ostringstream s;
  for (int k = 0; k < frames; ++k) s << (k ? "," : "") << k * scale;
  return s.str();
}

// Meshes `image_path` through the real client (time scale 3 and the end frames extended twice,
// so that every frame lies inside the mesh's time span and is sampled finely), exports every
// frame's slice and has VTK check the volumes: within 2 % of the voxels, per label.
void expect_slices_match_voxels(const std::string& image_path, int frames, double delta,
                                const std::string& dir) {
  RunningServer server(dir + "/data");
  const std::string mesh_path = dir + "/mesh.m4d";
  const RunResult submitted =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "submit", image_path, "--delta",
                   std::to_string(delta), "--time-scale", "3", "--extend-time", "2", "--wait",
                   "--out", mesh_path},
                  std::chrono::seconds(600));
  ASSERT_EQ(submitted.exit_code, 0) << submitted.output;

  const RunResult exported =
      run_command({MESH4D_CLIENT_BIN, "export", mesh_path, "--vtu", dir + "/vtu", "--boundary",
                   "--slices", frame_times(frames, 3)},
                  std::chrono::seconds(300));
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  EXPECT_TRUE(fs::exists(dir + "/vtu/slices.pvd"));
  EXPECT_TRUE(fs::exists(dir + "/vtu/boundary.pvd"));
  EXPECT_TRUE(fs::exists(dir + "/vtu/boundary_0000.vtu"));

  const RunResult checked = run_command(
      {"/usr/bin/python3", MESH4D_VTU_CHECK, image_path, dir + "/vtu", "0.02", "--time-scale", "3"},
      std::chrono::seconds(300));
  std::printf("%s\n", checked.output.c_str());
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
}

TEST(ClientExport, VentricleSlicesMatchTheVoxelVolumesInVtk) {
  const std::string dir = make_temp_dir("mesh4d-export");
  domain::write_nifti(domain::beating_ventricle_phantom(), dir + "/ventricle.nii.gz");
  expect_slices_match_voxels(dir + "/ventricle.nii.gz", 15, 2.5, dir);
}

TEST(ClientExport, PatientSlicesMatchTheVoxelVolumesInVtk) {
  const std::string patient = std::string(MESH4D_HEART_DATA_DIR) + "/Pat01_mse4d_label4d.nii.gz";
  if (!fs::exists(patient)) GTEST_SKIP() << "no patient data beside the repository: " << patient;
  expect_slices_match_voxels(patient, 25, 3, make_temp_dir("mesh4d-export-patient"));
}

TEST(ClientExport, MfemMeshbAndStatsDescribeTheFetchedMesh) {
  const std::string dir = make_temp_dir("mesh4d-export-fem");
  RunningServer server(dir + "/data");
  domain::write_nifti(domain::hypersphere_phantom(), dir + "/sphere.nii.gz");
  const std::string mesh_path = dir + "/sphere.m4d";
  ASSERT_EQ(run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "submit",
                         dir + "/sphere.nii.gz", "--delta", "3", "--wait", "--out", mesh_path},
                        std::chrono::seconds(120))
                .exit_code,
            0);
  const mesh::Mesh4 m = mesh::read_m4d(mesh_path);

  const RunResult exported =
      run_command({MESH4D_CLIENT_BIN, "export", mesh_path, "--mfem", dir + "/sphere.mfem",
                   "--mfem-geometry", "8", "--meshb", dir + "/sphere.mesh"});
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  std::ifstream mfem(dir + "/sphere.mfem");
  std::string line, previous;
  std::getline(mfem, line);
  EXPECT_EQ(line, "MFEM mesh v1.0");
  std::size_t elements = 0, eights = 0;
  while (std::getline(mfem, line)) {
    if (previous == "elements") elements = std::stoul(line);
    if (line.rfind("1 8 ", 0) == 0) ++eights;
    previous = line;
  }
  EXPECT_EQ(elements, m.pentatopes.size());
  EXPECT_EQ(eights, m.pentatopes.size()) << "every element: attribute 1, geometry 8";
  std::ifstream meshb(dir + "/sphere.mesh");
  std::string word;
  std::size_t pentatopes = 0;
  while (meshb >> word)
    if (word == "Pentatopes") meshb >> pentatopes;
  EXPECT_EQ(pentatopes, m.pentatopes.size());

  const RunResult stats = run_command({MESH4D_CLIENT_BIN, "stats", mesh_path, "--json"});
  ASSERT_EQ(stats.exit_code, 0) << stats.output;
  const auto j = nlohmann::json::parse(stats.output);
  EXPECT_EQ(j["pentatopes"].get<std::size_t>(), m.pentatopes.size());
  EXPECT_EQ(j["vertices"].get<std::size_t>(), m.vertices.size());
  EXPECT_LT(j["radius_edge_ratio"]["max"].get<double>(), 2.0);
  EXPECT_GE(j["normalized_volume"]["min"].get<double>(), 0.01);
  // The sphere's one label: one manifold piece, as the certificate computed here says.
  ASSERT_EQ(j["labels"].size(), 1u);
  EXPECT_EQ(j["labels"][0]["pieces"].get<std::size_t>(), 1u);
  EXPECT_EQ(j["labels"][0]["non_manifold_vertices"].get<std::size_t>(), 0u);
  EXPECT_TRUE(j["manifold"].get<bool>());
  const RunResult table = run_command({MESH4D_CLIENT_BIN, "stats", mesh_path});
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find("radius-edge ratio"), std::string::npos) << table.output;
}

TEST(ClientExport, EachFailureHasItsExitCodeAndOneClearLine) {
  const std::string dir = make_temp_dir("mesh4d-export-bad");
  std::ofstream(dir + "/junk.m4d") << "not a mesh";
  struct Case {
    std::vector<std::string> args;
    int code;
    const char* message;
  };
  const Case cases[] = {
      {{"export", dir + "/missing.m4d", "--vtu", dir + "/v"}, 2, "missing.m4d"},
      {{"stats", dir + "/missing.m4d"}, 2, "missing.m4d"},
      {{"export", dir + "/junk.m4d", "--vtu", dir + "/v"}, 6, "mesh4d-client: export:"},
      {{"stats", dir + "/junk.m4d"}, 6, "mesh4d-client: stats:"},
      {{"export", dir + "/junk.m4d"}, 2, "nothing to write"},
      {{"export", dir + "/junk.m4d", "--slices", "1,2", "--mfem", dir + "/x"}, 2, "needs --vtu"},
      {{"export", dir + "/junk.m4d", "--mfem-geometry", "-1", "--mfem", dir + "/x"},
       2,
       "mfem-geometry"},
  };
  for (const auto& c : cases) {
    std::vector<std::string> argv{MESH4D_CLIENT_BIN};
    argv.insert(argv.end(), c.args.begin(), c.args.end());
    const RunResult r = run_command(argv);
    SCOPED_TRACE(c.args.front() + " " + c.args[1]);
    EXPECT_EQ(r.exit_code, c.code) << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << r.output;
  }
  // A file that cannot be written: its folder is a file.
  domain::write_nifti(domain::hypersphere_phantom({12, 12, 12, 12}, {1, 1, 1, 1}, 4),
                      dir + "/tiny.nii.gz");
  std::ofstream(dir + "/file") << "x";
  RunningServer server(dir + "/data");
  const RunResult made =
      run_command({MESH4D_CLIENT_BIN, "--server", server.address(), "submit", dir + "/tiny.nii.gz",
                   "--delta", "2", "--wait", "--out", dir + "/tiny.m4d"},
                  std::chrono::seconds(60));
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const RunResult r =
      run_command({MESH4D_CLIENT_BIN, "export", dir + "/tiny.m4d", "--mfem", dir + "/file/x"});
  EXPECT_EQ(r.exit_code, 6) << r.output;
  EXPECT_NE(r.output.find("cannot write"), std::string::npos) << r.output;
}

// --wait rewrites one live line on a terminal (carriage return, erase to the end of the line),
// cut to the terminal's width, and prints plain lines when its output is a pipe.
TEST(ClientProgress, LiveLineOnATerminalPlainLinesOtherwise) {
  const std::string dir = make_temp_dir("mesh4d-progress");
  RunningServer server(dir + "/data");
  domain::write_nifti(domain::beating_ventricle_phantom(), dir + "/ventricle.nii.gz");
  const std::vector<std::string> submit{
      MESH4D_CLIENT_BIN, "--server", server.address(), "submit", dir + "/ventricle.nii.gz",
      "--delta",         "6",        "--wait"};
  // script(1) gives the client a pseudo-terminal and copies what it writes.
  // A narrow terminal: the live line must be cut to fit, or rewriting it would wrap.
  std::string command = "stty cols 60 rows 20; ";
  for (const auto& a : submit) command += "'" + a + "' ";
  const RunResult tty =
      run_command({"/usr/bin/script", "-qefc", command, "/dev/null"}, std::chrono::seconds(300));
  ASSERT_EQ(tty.exit_code, 0) << tty.output;
  EXPECT_NE(tty.output.find('\r'), std::string::npos);
  EXPECT_NE(tty.output.find("\x1b[K"), std::string::npos) << "the live line is rewritten";
  EXPECT_NE(tty.output.find("REFINING"), std::string::npos) << tty.output;
  std::size_t live_lines = 0;
  for (std::size_t at = tty.output.find('\r'); at != std::string::npos;
       at = tty.output.find('\r', at + 1)) {
    // (The terminal turns each "\n" into "\r\n": those are not live lines.)
    if (at + 1 < tty.output.size() && tty.output[at + 1] == '\n') continue;
    const std::size_t end = tty.output.find("\x1b[K", at);
    if (end == std::string::npos) continue;
    ++live_lines;
    EXPECT_LT(end - at - 1, 60u) << "a live line wider than the terminal";
  }
  EXPECT_GE(live_lines, 2u);

  const RunResult plain = run_command(submit, std::chrono::seconds(300));
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_EQ(plain.output.find("\x1b["), std::string::npos) << "no terminal codes in a pipe";
  std::size_t lines = 0;
  std::istringstream in(plain.output);
  for (std::string line; std::getline(in, line);) lines += line.find("REFINING") == 0;
  EXPECT_GE(lines, 2u) << plain.output;
}

}  // namespace
}  // namespace mesh4d::testing
