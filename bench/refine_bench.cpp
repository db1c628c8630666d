// refine_bench: sequential refinement on the phantoms, one row per run in the form of the
// paper's Table 2, plus pentatopes per second, insertions, and peak memory; the paper's rule
// order against R3-first on the same input. Each run is a forked child (its own peak memory).
//
// The paper's figures for scale: 145 pentatopes/s on its 40k-pentatope hypersphere, 184 with
// R3 first; Pat1 at δ = 5: 49,479 pentatopes, 4,709 vertices, 30,758 boundary tetrahedra.
// The five patients of ../shared/data/heart4d (when present) at δ = 5, with the files' spacing
// (all 25 frames) and with the paper's (1.77, 1.77, 6, 1; first 15 frames). Then Pat01's whole
// cycle against each frame meshed alone by CGAL Mesh_3 (frames_comparison.h).
#include <algorithm>
#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <string>

#include "bench_util.h"
#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "domain/surface_oracle.h"
#include "frames_comparison.h"
#include "mesh/mesh_check.h"
#include "refine/refiner.h"

using namespace mesh4d;

namespace {

struct Row {
  mesh::MeshStats stats;
  std::uint64_t insertions = 0;
  double peak_mb = 0;
  double seconds = 0;
};

using mesh4d::bench::status_kb;

// Runs in a child: the oracle and refinement of `image` with `params`; fixed-size results only.
struct Flat {
  std::uint64_t vertices, pentatopes, boundary, insertions, off_surface, pinched, relabeled;
  double shortest, rho_max, rho_mean, rho_std, tau_min, tau_mean, tau_std, seconds, peak_mb,
      repair_seconds;
  bool ok;
};

Flat run_child(const domain::LabelImage4& image, const refine::RefineParams& params) {
  const auto result = mesh4d::bench::run_in_child<Flat>([&] {
    domain::LabelImage4 closed = image;
    domain::validate_and_close(closed);
    const domain::SurfaceOracle oracle(closed);
    refine::Refiner refiner(oracle, params);
    const auto r = refiner.run();
    const mesh::BoundaryCheck check = mesh::check_boundary(r.mesh);
    const std::uint64_t off_surface = check.non_feature_uses, pinched = check.pinched;
    Flat out{r.stats.vertices,
             r.stats.pentatopes,
             r.stats.boundary_tetrahedra,
             0,
             off_surface,
             pinched,
             r.relabeled,
             r.stats.shortest_edge,
             r.stats.radius_edge_ratio.max,
             r.stats.radius_edge_ratio.mean,
             r.stats.radius_edge_ratio.stddev,
             r.stats.normalized_volume.min,
             r.stats.normalized_volume.mean,
             r.stats.normalized_volume.stddev,
             r.stats.elapsed_seconds,
             status_kb("VmHWM:") / 1024.0,
             r.repair_seconds,
             true};
    for (auto n : r.stats.insertions) out.insertions += n;
    return out;
  });
  return result ? *result : Flat{};
}

// --only TEXT: run just the rows whose name contains TEXT; --junction-spacing X: that spacing
// (relative to Δ) instead of the default, 0 for none; --seed N: that seed for the random
// picking instead of the default (the mesh, and so its size and time, depend on it: several
// seeds show how much of a difference between two builds is the mesh's and how much the code's).
std::string g_only;
double g_junction_spacing = refine::RefineParams{}.junction_spacing;
std::uint64_t g_seed = refine::RefineParams{}.seed;

void row(const char* name, const domain::LabelImage4& image, double delta,
         refine::RuleOrder order) {
  if (!g_only.empty() && std::string(name).find(g_only) == std::string::npos) return;
  refine::RefineParams params;
  params.delta = delta;
  params.rule_order = order;
  params.junction_spacing = g_junction_spacing;
  params.seed = g_seed;
  const Flat f = run_child(image, params);
  if (!f.ok) {
    std::printf("| %s | run failed |\n", name);
    return;
  }
  std::printf(
      "| %s | %s | %g | %llu | %llu | %llu | %.2f | %.2f / %.2f / %.2f | %.4f / %.2f / %.2f | "
      "%.2f | %.0f | %llu | %.0f | %llu | %llu | %llu | %.2f |\n",
      name, order == refine::RuleOrder::r3_first ? "R3 first" : "paper", delta,
      (unsigned long long)f.pentatopes, (unsigned long long)f.boundary,
      (unsigned long long)f.vertices, f.shortest, f.rho_max, f.rho_mean, f.rho_std, f.tau_min,
      f.tau_mean, f.tau_std, f.seconds, f.pentatopes / f.seconds, (unsigned long long)f.insertions,
      f.peak_mb, (unsigned long long)f.off_surface, (unsigned long long)f.pinched,
      (unsigned long long)f.relabeled, f.repair_seconds);
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--only") == 0) g_only = argv[i + 1];
    if (std::strcmp(argv[i], "--junction-spacing") == 0)
      g_junction_spacing = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--seed") == 0) g_seed = std::strtoull(argv[i + 1], nullptr, 10);
  }
  std::printf("Sequential refinement (R1-R5), one thread, junction spacing %g delta, seed %llu\n",
              g_junction_spacing, static_cast<unsigned long long>(g_seed));
  std::printf(
      "| input | rule order | δ | pentatopes | boundary tets | vertices | shortest edge | "
      "radius-edge max / mean / std | normalized volume min / mean / std | time s | "
      "pentatopes/s | insertions | peak MB | boundary vertex uses off ∂Ω | pinched triangles "
      "| relabeled pentatopes | of the time, pinch repair s "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  const auto sphere = domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
  row("hypersphere r=12", sphere, 2, refine::RuleOrder::r3_first);
  row("hypersphere r=12", sphere, 2, refine::RuleOrder::paper);
  const auto ventricle = domain::beating_ventricle_phantom();
  row("ventricle 100x100x44x15", ventricle, 5, refine::RuleOrder::r3_first);
  row("ventricle 100x100x44x15", ventricle, 5, refine::RuleOrder::paper);

  const std::string dir = MESH4D_HEART_DATA_DIR;
  for (int patient = 1; patient <= 5; ++patient) {
    const std::string file = dir + "/Pat0" + std::to_string(patient) + "_mse4d_label4d.nii.gz";
    if (!std::ifstream(file)) {
      std::printf("(no real data: %s is absent)\n", file.c_str());
      break;
    }
    const auto image = domain::read_label_image(file);
    const std::string name = "Pat0" + std::to_string(patient);
    row((name + ", file spacing, 25 frames").c_str(), image, 5, refine::RuleOrder::r3_first);
    const auto& d = image.dims();
    domain::LabelImage4 paper({d[0], d[1], d[2], 15}, {1.77, 1.77, 6, 1});
    for (std::size_t i = 0; i < paper.voxel_count(); ++i)
      if (image.at(i) != 0) paper.set(i, image.at(i));
    row((name + ", paper spacing, 15 frames").c_str(), paper, 5, refine::RuleOrder::r3_first);
  }
  const std::string pat01 = dir + "/Pat01_mse4d_label4d.nii.gz";
  if (std::ifstream(pat01) && (g_only.empty() || g_only == "Mesh_3"))
    mesh4d::bench::compare_with_mesh3_frames("Pat01 (files' spacing, 25 frames)",
                                             domain::read_label_image(pat01), 5);
  return 0;
}
