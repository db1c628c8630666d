#include "frames_comparison.h"

#include <cmath>
#include <cstdio>

#include "bench_util.h"
#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "domain/time_scale.h"
#include "mesh/mesh_slice.h"
#include "mesh3_frames.h"
#include "refine/periodic_time.h"
#include "refine/time_caps.h"

namespace mesh4d::bench {
namespace {

constexpr std::size_t kMaxFrames = 64;

// What the 4D run sends back from its child process: its time and each frame's slice volumes.
struct SliceVolumes {
  double seconds = 0;
  std::uint64_t pentatopes = 0;
  double time_scale = 0;
  double volume[kMaxFrames][2] = {};
  bool ok = false;
};

// The 4D refinement in a forked child (its memory its own, as in the other rows), as a job with
// `--delta` alone runs it: cleaned, at the time scale chosen from the data, with time caps or
// in periodic time.
SliceVolumes refine_and_slice(const domain::LabelImage4& image, double delta, bool periodic,
                              bool sag_offset) {
  const auto result = run_in_child<SliceVolumes>([&] {
    domain::LabelImage4 meshed = image;
    meshed.set_time_spacing(domain::automatic_time_scale(image, delta, periodic));
    domain::clean_segmentation(meshed, domain::kDefaultMinIslandVoxels);
    refine::RefineParams params;
    params.delta = delta;
    params.sag_offset = sag_offset;
    std::vector<std::string> warnings;
    const auto r = periodic ? refine::refine_periodic(meshed, params, nullptr, &warnings)
                            : refine::refine_with_time_caps(meshed, params, nullptr, &warnings);
    SliceVolumes s;
    s.seconds = r.stats.elapsed_seconds;
    s.pentatopes = r.stats.pentatopes;
    s.time_scale = meshed.spacing()[3];
    for (std::size_t t = 0; t < image.dims()[3] && t < kMaxFrames; ++t) {
      const auto v = mesh::slice_volumes(r.mesh, meshed.voxel_center(0, 0, 0, t)[3]);
      for (int l = 0; l < 2; ++l) s.volume[t][l] = v.count(l + 1) ? v.at(l + 1) : 0;
    }
    s.ok = true;
    return s;
  });
  return result ? *result : SliceVolumes{};
}

double percent_error(double v, double reference) {
  return reference > 0 ? 100 * (v - reference) / reference : 0;
}

}  // namespace

FramesSummary compare_with_mesh3_frames(const char* name, const domain::LabelImage4& image,
                                        double delta, bool print_frames, bool sag_offset) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const double voxel = s[0] * s[1] * s[2];
  FramesSummary summary;
  const SliceVolumes ours[2] = {refine_and_slice(image, delta, false, sag_offset),
                                refine_and_slice(image, delta, true, sag_offset)};
  if (!ours[0].ok || !ours[1].ok) {
    std::printf("%s: a 4D run failed\n", name);
    return summary;
  }
  if (print_frames) {
    std::printf(
        "\n%s, δ = %g, time scale %g (chosen from the data): the 4D mesh's cross-section at each "
        "frame, in open time (time caps) and periodic time, against CGAL Mesh_3 on the frame "
        "alone (facet size δ, facet distance 1, radius-edge 2, perturb, exude); volume errors "
        "against the voxel volume\n",
        name, delta, ours[0].time_scale);
    std::printf(
        "| frame | voxel volume cavity / myocardium (mm³) | mesh4d open, cavity / myocardium | "
        "mesh4d periodic, cavity / myocardium | Mesh_3, cavity / myocardium | Mesh_3 tetrahedra "
        "| Mesh_3 s |\n|---|---|---|---|---|---|---|\n");
  }
  std::size_t frames = 0;
  for (std::size_t t = 0; t < d[3] && t < kMaxFrames; ++t, ++frames) {
    double reference[2] = {0, 0};
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) {
          const auto l = image.at(x, y, z, t);
          if (l == 1 || l == 2) reference[l - 1] += voxel;
        }
    const FrameMesh m = mesh_frame_with_cgal(image, t, delta, 1.0);
    summary.seconds[2] += m.seconds;
    double e[kMeshers][2];
    for (int l = 0; l < 2; ++l) {
      for (int k = 0; k < 2; ++k) e[k][l] = percent_error(ours[k].volume[t][l], reference[l]);
      const auto it = m.volume.find(static_cast<domain::Label>(l + 1));
      e[2][l] = percent_error(it == m.volume.end() ? 0 : it->second, reference[l]);
      for (int k = 0; k < kMeshers; ++k) {
        summary.mean[k][l] += std::abs(e[k][l]);
        if (std::abs(e[k][l]) > std::abs(summary.worst[k][l])) summary.worst[k][l] = e[k][l];
      }
    }
    if (print_frames)
      std::printf(
          "| %zu | %.0f / %.0f | %+.1f %% / %+.1f %% | %+.1f %% / %+.1f %% | %+.1f %% / %+.1f %% "
          "| %zu | %.2f |\n",
          t, reference[0], reference[1], e[0][0], e[0][1], e[1][0], e[1][1], e[2][0], e[2][1],
          m.cells, m.seconds);
    std::fflush(stdout);
  }
  for (auto& mesher : summary.mean)
    for (double& m : mesher) m /= static_cast<double>(frames);
  for (int k = 0; k < 2; ++k) {
    summary.seconds[k] = ours[k].seconds;
    summary.pentatopes[k] = ours[k].pentatopes;
    summary.time_scale[k] = ours[k].time_scale;
  }
  summary.ok = true;
  if (print_frames)
    std::printf(
        "\nmesh4d, the whole cycle in 4D: open %.1f s (%llu pentatopes), periodic %.1f s (%llu "
        "pentatopes); Mesh_3, frame by frame: %.1f s in all\n",
        ours[0].seconds, static_cast<unsigned long long>(ours[0].pentatopes), ours[1].seconds,
        static_cast<unsigned long long>(ours[1].pentatopes), summary.seconds[2]);
  return summary;
}

void print_frames_summaries(const std::vector<std::pair<std::string, FramesSummary>>& rows,
                            double delta) {
  std::printf(
      "\nEvery frame's volume error per label against its voxels (mean |error| / worst frame), "
      "δ = %g: mesh4d's 4D mesh (time scale chosen from the data) in open time (time caps) and "
      "in periodic time, beside Mesh_3 frame by frame (facet distance 1)\n"
      "| image | time scale open / periodic | open: cavity | open: myocardium | periodic: "
      "cavity | periodic: myocardium | Mesh_3: cavity | Mesh_3: myocardium | open s "
      "(pentatopes) | periodic s (pentatopes) | Mesh_3 s |\n"
      "|---|---|---|---|---|---|---|---|---|---|---|\n",
      delta);
  for (const auto& [name, r] : rows) {
    if (!r.ok) continue;
    std::printf("| %s | %g / %g |", name.c_str(), r.time_scale[0], r.time_scale[1]);
    for (int k = 0; k < kMeshers; ++k)
      for (int l = 0; l < 2; ++l) std::printf(" %.1f %% / %+.1f %% |", r.mean[k][l], r.worst[k][l]);
    std::printf(" %.1f (%llu) | %.1f (%llu) | %.1f |\n", r.seconds[0],
                static_cast<unsigned long long>(r.pentatopes[0]), r.seconds[1],
                static_cast<unsigned long long>(r.pentatopes[1]), r.seconds[2]);
  }
  std::fflush(stdout);
}

}  // namespace mesh4d::bench
