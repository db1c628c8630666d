// export: writes a .m4d mesh for viewers and solvers. Time slices (the 3D mesh at t = const)
// go to VTK XML files with a .pvd collection that ParaView plays as an animation; the whole 4D
// mesh goes to MFEM's v1.0 format or libMeshb's ASCII .mesh.
#include <CLI/CLI.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>

#include "exit_codes.h"
#include "mesh/fem_export.h"
#include "mesh/mesh_io.h"
#include "mesh/mesh_slice.h"
#include "mesh/vtu_writer.h"
#include "mesh_file_commands.h"

namespace mesh4d::client {
namespace {

struct ExportOptions {
  std::string mesh;
  std::vector<double> slices;
  std::string vtu_dir;
  bool boundary = false;
  std::string mfem;
  int mfem_geometry = mesh::kMfemPentatopeDefault;
  std::string meshb;
};

void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

// Without --slices: every whole time unit strictly inside the mesh's time span (the frames of
// an image with time spacing 1).
// In periodic time, every whole time unit of the period.
std::vector<double> default_slices(const mesh::Mesh4& m) {
  std::vector<double> times;
  if (m.periodic()) {
    for (double t = std::ceil(m.period_start);
         t < m.period_start + m.period && times.size() < 10000; t += 1)
      times.push_back(t);
    return times;
  }
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& p : m.vertices) lo = std::min(lo, p[3]), hi = std::max(hi, p[3]);
  for (double t = std::floor(lo) + 1; t < hi && times.size() < 10000; t += 1) times.push_back(t);
  return times;
}

void export_slices(const mesh::Mesh4& m, const ExportOptions& o) {
  const std::filesystem::path dir(o.vtu_dir);
  std::filesystem::create_directories(dir);
  const std::vector<double> times = o.slices.empty() ? default_slices(m) : o.slices;
  if (times.empty()) throw std::runtime_error("the mesh spans no whole time unit: give --slices");
  std::vector<std::pair<double, std::string>> volumes, boundaries;
  for (std::size_t i = 0; i < times.size(); ++i) {
    const mesh::SliceMesh slice = mesh::slice_mesh(m, times[i], o.boundary);
    char name[48];
    std::snprintf(name, sizeof name, "slice_%04zu.vtu", i);
    write_text(dir / name, mesh::slice_vtu(m, slice));
    volumes.emplace_back(times[i], name);
    if (o.boundary) {
      std::snprintf(name, sizeof name, "boundary_%04zu.vtu", i);
      write_text(dir / name, mesh::slice_boundary_vtu(slice));
      boundaries.emplace_back(times[i], name);
    }
    std::cout << "t = " << times[i] << ": " << slice.tetrahedra.size() << " tetrahedra";
    if (o.boundary) std::cout << ", " << slice.triangles.size() << " boundary triangles";
    std::cout << "\n";
  }
  write_text(dir / "slices.pvd", mesh::pvd_collection(volumes));
  if (o.boundary) write_text(dir / "boundary.pvd", mesh::pvd_collection(boundaries));
  std::cout << "wrote " << times.size() << " slices to " << (dir / "slices.pvd").string() << "\n";
}

int run_export(const ExportOptions& o) {
  if (o.vtu_dir.empty() && o.mfem.empty() && o.meshb.empty()) {
    std::cerr << "mesh4d-client: export: nothing to write: give --vtu DIR, --mfem FILE or "
                 "--meshb FILE\n";
    return kExitUsage;
  }
  if (!o.slices.empty() && o.vtu_dir.empty()) {
    std::cerr << "mesh4d-client: export: --slices needs --vtu DIR\n";
    return kExitUsage;
  }
  try {
    const mesh::Mesh4 m = mesh::read_m4d(o.mesh);
    if (!o.vtu_dir.empty()) export_slices(m, o);
    if (!o.mfem.empty()) {
      write_text(o.mfem, mesh::mfem_mesh(m, o.mfem_geometry));
      std::cout << "wrote " << o.mfem << " (MFEM mesh v1.0, pentatope geometry " << o.mfem_geometry
                << ")\n";
      if (m.periodic()) {
        write_text(o.mfem + ".v2v", mesh::mfem_periodic_vertex_map(m));
        std::cout << "wrote " << o.mfem << ".v2v (periodic in time, period " << m.period
                  << ": the vertex map for Mesh::MakePeriodic)\n";
      }
    }
    if (!o.meshb.empty()) {
      write_text(o.meshb, mesh::meshb_mesh(m));
      std::cout << "wrote " << o.meshb << " (libMeshb ASCII, Pentatopes)\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "mesh4d-client: export: " << e.what() << "\n";
    return kExitLocal;
  }
  return kExitOk;
}

}  // namespace

void setup_export_command(CLI::App& app, int* exit_code) {
  auto o = std::make_shared<ExportOptions>();
  CLI::App* cmd = app.add_subcommand(
      "export", "write a .m4d mesh as VTK time slices (ParaView), MFEM or libMeshb files");
  cmd->add_option("MESH", o->mesh, ".m4d mesh (from fetch or submit --out)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--slices", o->slices,
                  "times to cut at, comma-separated (default: every whole time unit inside the "
                  "mesh)")
      ->delimiter(',');
  cmd->add_option("--vtu", o->vtu_dir,
                  "directory for slice_NNNN.vtu files and slices.pvd (created if missing)");
  cmd->add_flag("--boundary", o->boundary,
                "with --vtu, also the sliced boundary surface (boundary_NNNN.vtu, boundary.pvd)");
  cmd->add_option("--mfem", o->mfem, "write the 4D mesh in MFEM mesh v1.0 format");
  cmd->add_option("--mfem-geometry", o->mfem_geometry,
                  "MFEM's geometry code for the pentatope (7 in mfem's data/cube4d_24.MFEM; "
                  "other 4D branches differ)")
      ->check(CLI::Range(0, 255));
  cmd->add_option("--meshb", o->meshb, "write the 4D mesh as a libMeshb ASCII .mesh");
  cmd->callback([o, exit_code] { *exit_code = run_export(*o); });
}

}  // namespace mesh4d::client
