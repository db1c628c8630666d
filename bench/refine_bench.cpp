// refine_bench: sequential refinement on the phantoms, one row per run in the form of the
// paper's Table 2, plus pentatopes per second, insertions, and peak memory; the paper's rule
// order against R3-first on the same input. Each run is a forked child (its own peak memory).
// `--threads N` runs the parallel refiner instead, for the same checks on its meshes.
//
// The paper's figures for scale: 145 pentatopes/s on its 40k-pentatope hypersphere, 184 with
// R3 first; Pat1 at δ = 5: 49,479 pentatopes, 4,709 vertices, 30,758 boundary tetrahedra.
// The five patients of ../shared/data/heart4d (when present) at δ = 5, with the files' spacing
// (all 25 frames), with the default time scale (all 25 frames) and with the paper's spacing
// (1.77, 1.77, 6, 1; first 15 frames). Then each patient's whole cycle, as a job with `--delta 5`
// alone meshes it, against each frame meshed alone by CGAL Mesh_3 (frames_comparison.h).
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "bench_util.h"
#include "domain/image_io.h"
#include "domain/phantoms.h"
#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "domain/time_scale.h"
#include "frames_comparison.h"
#include "mesh/mesh_check.h"
#include "refine/fidelity_certificate.h"
#include "refine/periodic_time.h"
#include "refine/refiner.h"
#include "refine/time_caps.h"
#include "refine/two_sided_distance.h"

using namespace mesh4d;

namespace {

struct Row {
  mesh::MeshStats stats;
  std::uint64_t insertions = 0;
  double peak_mb = 0;
  double seconds = 0;
};

using mesh4d::bench::status_kb;

// --min-island-voxels N: the segmentation cleanup's threshold (the service's default otherwise;
// 0: none).
std::size_t g_min_island_voxels = domain::kDefaultMinIslandVoxels;
// --time-caps off: the image closed with background half a frame past its ends, as before the
// time caps (refine/time_caps.h), for comparison.
bool g_time_caps = true;
// --time periodic: every row meshed in periodic time (refine/periodic_time.h), the cycle's last
// frame next to its first.
bool g_periodic = false;
// --images Pat03,ventricle: the Mesh_3 comparison on these images only (all: empty).
std::string g_images;
bool wanted(const std::string& image) {
  return g_images.empty() || ("," + g_images + ",").find("," + image + ",") != std::string::npos;
}

// Runs in a child: the cleanup, oracle and refinement of `image` with `params`; fixed-size
// results only.
struct Flat {
  std::uint64_t vertices, pentatopes, boundary, insertions, off_surface, pinched, relabeled,
      fingerprint;
  // The topology certificate, summed over the labels.
  std::uint64_t pieces, touching, nm_vertices, nm_edges, nm_triangles, image_pieces;
  double volume_ratio;       // the mesh's 4-volume over the voxels', all labels
  double worst_frame_error;  // of any label's section at a frame against its voxels
  double certificate_seconds;
  double mesh_to_image_max, image_to_mesh_max;  // the two-sided distance, largest over labels
  double distance_seconds;                      // of the certificate's time, the distance
  double shortest, rho_max, rho_mean, rho_std, tau_min, tau_mean, tau_std, seconds, peak_mb,
      repair_seconds;
  bool ok;
  std::uint64_t manifold_points, manifold_rounds;            // the manifold sampling's
  std::uint64_t pieces_removed, pieces_bridged, pieces_cut;  // the piece matching's
  double sag_seconds, largest_offset;                        // the sag offset's
  refine::StageSeconds stages;                               // where the refinement's time went
};

Flat run_child(const domain::LabelImage4& image, const refine::RefineParams& params) {
  const auto result = mesh4d::bench::run_in_child<Flat>([&] {
    // As a job prepares it: cleaned, then closed (with the time caps' ghost frames, unless
    // --time-caps off).
    domain::LabelImage4 closed = image;
    domain::clean_segmentation(closed, g_min_island_voxels);
    std::vector<std::string> warnings;
    const auto r = [&] {
      if (g_periodic) return refine::refine_periodic(closed, params, nullptr, &warnings);
      if (g_time_caps) return refine::refine_with_time_caps(closed, params, nullptr, &warnings);
      domain::validate_and_close(closed);
      const domain::SurfaceOracle oracle(closed);
      return refine::refine(oracle, params);
    }();
    const mesh::BoundaryCheck check = mesh::check_boundary(r.mesh);
    const std::uint64_t off_surface = check.non_feature_uses, pinched = check.pinched;
    Flat out{r.stats.vertices,
             r.stats.pentatopes,
             r.stats.boundary_tetrahedra,
             0,
             off_surface,
             pinched,
             r.relabeled,
             mesh4d::bench::mesh_fingerprint(r.mesh),
             0,
             0,
             0,
             0,
             0,
             0,
             0,
             0,
             0,
             0,
             0,
             0,
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
             true,
             r.manifold_points,
             static_cast<std::uint64_t>(r.manifold_rounds),
             r.pieces_removed,
             r.pieces_bridged,
             r.pieces_cut,
             r.sag.seconds,
             r.sag.largest_offset,
             r.stages};
    for (auto n : r.stats.insertions) out.insertions += n;
    // The certificate a job computes after refinement (not in the rate: timed on its own).
    const auto t0 = std::chrono::steady_clock::now();
    const refine::FidelityCertificate certificate = refine::certify(r.mesh, closed);
    out.certificate_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const auto t1 = std::chrono::steady_clock::now();
    refine::two_sided_distances(r.mesh, closed);  // timed again on its own
    out.distance_seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
    double mesh_volume = 0, voxel_volume = 0;
    for (const refine::LabelFidelity& l : certificate.labels) {
      mesh_volume += l.volume;
      voxel_volume += l.voxel_volume;
      out.image_pieces += l.image_pieces;
      out.pieces += l.mesh_pieces;
      out.touching += l.touching_pieces;
      out.nm_vertices += l.non_manifold_vertices;
      out.nm_edges += l.non_manifold_edges;
      out.nm_triangles += l.non_manifold_triangles;
      if (std::abs(l.worst_frame_error) > std::abs(out.worst_frame_error))
        out.worst_frame_error = l.worst_frame_error;
      out.mesh_to_image_max = std::max(out.mesh_to_image_max, l.mesh_to_image_max);
      out.image_to_mesh_max = std::max(out.image_to_mesh_max, l.image_to_mesh_max);
    }
    out.volume_ratio = voxel_volume > 0 ? mesh_volume / voxel_volume : 0;
    return out;
  });
  return result ? *result : Flat{};
}

// --only TEXT: run just the rows whose name contains TEXT; --junction-spacing X: that spacing
// (relative to Δ) instead of the default, 0 for none; --seed N: that seed for the random
// picking instead of the default (the mesh, and so its size and time, depend on it: several
// seeds show how much of a difference between two builds is the mesh's and how much the code's).
// --seeds A,B,C: each row once per seed, then a table of the rates' medians over the seeds.
std::string g_only;
// --sag-offset off: every boundary vertex left on ∂Ω (refine/facet_sag.h), for comparison.
bool g_sag_offset = true;
// --frame-fit off: no fit of the frames' volumes after the offset (refine/frame_volume_fit.h).
bool g_frame_fit = true;
double g_junction_spacing = refine::RefineParams{}.junction_spacing;
std::uint64_t g_seed = refine::RefineParams{}.seed;
std::vector<std::uint64_t> g_seeds;
// --threads N: the same rows with the parallel refiner on N threads (its meshes must pass the
// same checks; with more than one thread a seed does not fix the mesh).
unsigned g_threads = 1;

// --stages on: after the table, each row's refinement time by stage (refine/refiner.h: Stage).
bool g_stages = false;
std::vector<std::pair<std::string, refine::StageSeconds>> g_stage_rows;

struct OverSeeds {
  std::string name, order;
  std::vector<double> rates;
  bool all_pass = true;
};
std::vector<OverSeeds> g_over_seeds;

// One mesh: its Table-2 row; true when it passes the fidelity and quality checks.
bool mesh_row(const std::string& name, const domain::LabelImage4& image, double delta,
              refine::RuleOrder order, std::uint64_t seed, double* rate) {
  refine::RefineParams params;
  params.delta = delta;
  params.rule_order = order;
  params.junction_spacing = g_junction_spacing;
  params.seed = seed;
  params.threads = g_threads;
  params.sag_offset = g_sag_offset;
  params.fit_frame_volumes = g_frame_fit;
  const Flat f = run_child(image, params);
  if (!f.ok) {
    std::printf("| %s | run failed |\n", name.c_str());
    return false;
  }
  *rate = f.pentatopes / f.seconds;
  g_stage_rows.push_back({name, f.stages});
  std::printf(
      "| %s | %s | %g | %llu | %llu | %llu | %.2f | %.2f / %.2f / %.2f | %.4f / %.2f / %.2f | "
      "%.2f | %.0f | %llu | %.0f | %llu | %llu | %llu | %.2f | %.2f (%.2f) | %llu (%llu) | %llu / "
      "%llu / %llu "
      "| %llu / %llu / %llu | "
      "%llu / %llu / "
      "%llu | "
      "%.4f | %+.3f | %.2f / %.2f | %.2f (%.2f) | "
      "%016llx |\n",
      name.c_str(), order == refine::RuleOrder::r3_first ? "R3 first" : "paper", delta,
      (unsigned long long)f.pentatopes, (unsigned long long)f.boundary,
      (unsigned long long)f.vertices, f.shortest, f.rho_max, f.rho_mean, f.rho_std, f.tau_min,
      f.tau_mean, f.tau_std, f.seconds, f.pentatopes / f.seconds, (unsigned long long)f.insertions,
      f.peak_mb, (unsigned long long)f.off_surface, (unsigned long long)f.pinched,
      (unsigned long long)f.relabeled, f.repair_seconds, f.sag_seconds, f.largest_offset,
      (unsigned long long)f.manifold_points, (unsigned long long)f.manifold_rounds,
      (unsigned long long)f.pieces_removed, (unsigned long long)f.pieces_bridged,
      (unsigned long long)f.pieces_cut, (unsigned long long)f.pieces,
      (unsigned long long)f.touching, (unsigned long long)f.image_pieces,
      (unsigned long long)f.nm_vertices, (unsigned long long)f.nm_edges,
      (unsigned long long)f.nm_triangles, f.volume_ratio, f.worst_frame_error, f.mesh_to_image_max,
      f.image_to_mesh_max, f.certificate_seconds, f.distance_seconds,
      (unsigned long long)f.fingerprint);
  std::fflush(stdout);
  return f.off_surface == 0 && f.pinched == 0 && f.rho_max <= params.radius_edge_bound &&
         f.tau_min >= params.sliver_bound;
}

void row(const char* name, const domain::LabelImage4& image, double delta,
         refine::RuleOrder order) {
  if (!g_only.empty() && std::string(name).find(g_only) == std::string::npos) return;
  double rate = 0;
  if (g_seeds.empty()) {
    mesh_row(name, image, delta, order, g_seed, &rate);
    return;
  }
  OverSeeds over{name, order == refine::RuleOrder::r3_first ? "R3 first" : "paper", {}, true};
  for (std::uint64_t seed : g_seeds) {
    const bool pass = mesh_row(std::string(name) + ", seed " + std::to_string(seed), image, delta,
                               order, seed, &rate);
    over.all_pass = over.all_pass && pass;
    over.rates.push_back(rate);
  }
  g_over_seeds.push_back(over);
}

void print_stages() {
  if (!g_stages || g_stage_rows.empty()) return;
  std::printf(
      "\nWhere each row's refinement time went (s; the rules inside every stage counted "
      "apart)\n| input |");
  for (int i = 0; i < refine::kStages; ++i)
    std::printf(" %s |", refine::stage_name(static_cast<refine::Stage>(i)));
  std::printf(" total |\n|---|");
  for (int i = 0; i <= refine::kStages; ++i) std::printf("---|");
  std::printf("\n");
  for (const auto& [name, stages] : g_stage_rows) {
    std::printf("| %s |", name.c_str());
    double total = 0;
    for (double s : stages.seconds) std::printf(" %.3f |", s), total += s;
    std::printf(" %.3f |\n", total);
  }
  std::fflush(stdout);
}

void print_over_seeds() {
  if (g_over_seeds.empty()) return;
  std::printf(
      "\nPentatopes per second over seeds (each seed its own mesh)\n| input | rule order | seeds | "
      "median | min | max | every mesh passed the checks |\n|---|---|---|---|---|---|---|\n");
  for (OverSeeds& o : g_over_seeds) {
    std::sort(o.rates.begin(), o.rates.end());
    const std::size_t n = o.rates.size();
    const double median = n % 2 ? o.rates[n / 2] : 0.5 * (o.rates[n / 2 - 1] + o.rates[n / 2]);
    std::printf("| %s | %s | %zu | %.0f | %.0f | %.0f | %s |\n", o.name.c_str(), o.order.c_str(), n,
                median, o.rates.front(), o.rates.back(), o.all_pass ? "yes" : "NO");
  }
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--time-caps") == 0) g_time_caps = std::strcmp(argv[i + 1], "off");
    if (std::strcmp(argv[i], "--time") == 0) g_periodic = !std::strcmp(argv[i + 1], "periodic");
    if (std::strcmp(argv[i], "--only") == 0) g_only = argv[i + 1];
    if (std::strcmp(argv[i], "--images") == 0) g_images = argv[i + 1];
    if (std::strcmp(argv[i], "--sag-offset") == 0) g_sag_offset = std::strcmp(argv[i + 1], "off");
    if (std::strcmp(argv[i], "--frame-fit") == 0) g_frame_fit = std::strcmp(argv[i + 1], "off");
    if (std::strcmp(argv[i], "--stages") == 0) g_stages = std::strcmp(argv[i + 1], "off");
    if (std::strcmp(argv[i], "--min-island-voxels") == 0)
      g_min_island_voxels = std::strtoull(argv[i + 1], nullptr, 10);
    if (std::strcmp(argv[i], "--junction-spacing") == 0)
      g_junction_spacing = std::atof(argv[i + 1]);
    if (std::strcmp(argv[i], "--seed") == 0) g_seed = std::strtoull(argv[i + 1], nullptr, 10);
    if (std::strcmp(argv[i], "--threads") == 0)
      g_threads = static_cast<unsigned>(std::max(1L, std::strtol(argv[i + 1], nullptr, 10)));
    if (std::strcmp(argv[i], "--seeds") == 0)
      for (const char* p = argv[i + 1]; *p;) {
        char* end = nullptr;
        g_seeds.push_back(std::strtoull(p, &end, 10));
        if (end == p) break;
        p = *end == ',' ? end + 1 : end;
      }
  }
  std::string seeds = "seed " + std::to_string(g_seed);
  for (std::size_t k = 0; k < g_seeds.size(); ++k) {
    if (k == 0) seeds = "seeds ";
    if (k > 0) seeds.push_back(',');
    seeds.append(std::to_string(g_seeds[k]));
  }
  std::printf(
      "%s (R1-R5), %u thread%s, junction spacing %g delta, %s, %s time, sag "
      "offset %s, frame volume fit %s\n",
      g_threads > 1 ? "Parallel refinement" : "Sequential refinement", g_threads,
      g_threads > 1 ? "s" : "", g_junction_spacing, seeds.c_str(),
      g_periodic ? "periodic" : (g_time_caps ? "open (time caps)" : "open (no caps)"),
      g_sag_offset ? "on" : "off", g_sag_offset && g_frame_fit ? "on" : "off");
  std::printf(
      "| input | rule order | δ | pentatopes | boundary tets | vertices | shortest edge | "
      "radius-edge max / mean / std | normalized volume min / mean / std | time s | "
      "pentatopes/s | insertions | peak MB | boundary vertex uses off ∂Ω | pinched triangles "
      "| relabeled pentatopes | of the time, pinch repair s | of the time, sag offset s (largest "
      "offset) | manifold sampling points (rounds) "
      "| pieces removed / bridged / cut | mesh pieces / touching another / "
      "image pieces (all labels) | non-manifold vertices / edges / triangles | 4-volume / voxels "
      "| worst frame volume error | boundary distance max, mesh → image / image → mesh | "
      "certificate s (of which the distance) | mesh fingerprint "
      "|\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
      "---|---|---|---|---|\n");
  const auto sphere = domain::hypersphere_phantom({32, 32, 32, 32}, {1, 1, 1, 1}, 12);
  row("hypersphere r=12", sphere, 2, refine::RuleOrder::r3_first);
  row("hypersphere r=12", sphere, 2, refine::RuleOrder::paper);
  const auto ventricle = domain::beating_ventricle_phantom();
  row("ventricle 100x100x44x15", ventricle, 5, refine::RuleOrder::r3_first);
  row("ventricle 100x100x44x15", ventricle, 5, refine::RuleOrder::paper);
  // The phantoms that provoke the certificate's defects (24⁴ voxels of 1 unit), at δ 2.5.
  for (const char* name : {"thin-wall", "checkerboard", "corner-contact", "island", "thin-plate",
                           "moving-junction", "diagonal-island", "thin-bridge"})
    row(name, domain::make_phantom(name), 2.5, refine::RuleOrder::r3_first);

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
    // What `--delta 5` alone gives: the time scale chosen from the data (domain/time_scale.h).
    domain::LabelImage4 scaled = image;
    scaled.set_time_spacing(domain::automatic_time_scale(image, 5, g_periodic));
    row((name + ", default time scale, 25 frames").c_str(), scaled, 5, refine::RuleOrder::r3_first);
    const auto& d = image.dims();
    domain::LabelImage4 paper({d[0], d[1], d[2], 15}, {1.77, 1.77, 6, 1});
    for (std::size_t i = 0; i < paper.voxel_count(); ++i)
      if (image.at(i) != 0) paper.set(i, image.at(i));
    row((name + ", paper spacing, 15 frames").c_str(), paper, 5, refine::RuleOrder::r3_first);
  }
  print_over_seeds();
  print_stages();
  // Each patient's frames against Mesh_3's (the per-frame table for Pat01), then one row each.
  if (g_only.empty() || g_only == "Mesh_3") {
    std::vector<std::pair<std::string, mesh4d::bench::FramesSummary>> summaries;
    for (int patient = 1; patient <= 5; ++patient) {
      const std::string name = "Pat0" + std::to_string(patient);
      const std::string file = dir + "/" + name + "_mse4d_label4d.nii.gz";
      if (!std::ifstream(file)) break;
      if (!wanted(name)) continue;
      summaries.emplace_back(
          name, mesh4d::bench::compare_with_mesh3_frames(
                    name.c_str(), domain::read_label_image(file), 5, patient == 1, g_sag_offset));
    }
    if (wanted("ventricle"))
      summaries.emplace_back("ventricle", mesh4d::bench::compare_with_mesh3_frames(
                                              "ventricle", domain::beating_ventricle_phantom(), 5,
                                              false, g_sag_offset));
    mesh4d::bench::print_frames_summaries(summaries, 5);
  }
  return 0;
}
