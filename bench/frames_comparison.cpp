#include "frames_comparison.h"

#include <cmath>
#include <cstdio>

#include "bench_util.h"
#include "domain/segmentation_cleanup.h"
#include "domain/surface_oracle.h"
#include "domain/time_scale.h"
#include "mesh/mesh_slice.h"
#include "mesh3_frames.h"
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
// `--delta` alone runs it: cleaned, at the time scale chosen from the data, with time caps.
SliceVolumes refine_and_slice(const domain::LabelImage4& image, double delta) {
  const auto result = run_in_child<SliceVolumes>([&] {
    domain::LabelImage4 meshed = image;
    meshed.set_time_spacing(domain::automatic_time_scale(image, delta));
    domain::clean_segmentation(meshed, domain::kDefaultMinIslandVoxels);
    refine::RefineParams params;
    params.delta = delta;
    std::vector<std::string> warnings;
    const auto r = refine::refine_with_time_caps(meshed, params, nullptr, &warnings);
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
                                        double delta, bool print_frames) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const double voxel = s[0] * s[1] * s[2];
  FramesSummary summary;
  const SliceVolumes ours = refine_and_slice(image, delta);
  if (!ours.ok) {
    std::printf("%s: the 4D run failed\n", name);
    return summary;
  }
  if (print_frames) {
    std::printf(
        "\n%s, δ = %g, time scale %g (chosen from the data), time caps: the 4D mesh's "
        "cross-section at each frame against CGAL Mesh_3 on the frame alone (facet size δ, facet "
        "distance 1, radius-edge 2, perturb, exude); volume errors against the voxel volume\n",
        name, delta, ours.time_scale);
    std::printf(
        "| frame | voxel volume cavity / myocardium (mm³) | mesh4d error cavity / myocardium"
        " | Mesh_3 error cavity / myocardium | Mesh_3 tetrahedra | Mesh_3 s |\n"
        "|---|---|---|---|---|---|\n");
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
    summary.seconds[1] += m.seconds;
    double e[2][2];
    for (int l = 0; l < 2; ++l) {
      e[0][l] = percent_error(ours.volume[t][l], reference[l]);
      const auto it = m.volume.find(static_cast<domain::Label>(l + 1));
      e[1][l] = percent_error(it == m.volume.end() ? 0 : it->second, reference[l]);
      for (int k = 0; k < 2; ++k) {
        summary.mean[k][l] += std::abs(e[k][l]);
        if (std::abs(e[k][l]) > std::abs(summary.worst[k][l])) summary.worst[k][l] = e[k][l];
      }
    }
    if (print_frames)
      std::printf(
          "| %zu | %.0f / %.0f | %+.1f %% / %+.1f %% | %+.1f %% / %+.1f %% | %zu | %.2f |\n", t,
          reference[0], reference[1], e[0][0], e[0][1], e[1][0], e[1][1], m.cells, m.seconds);
    std::fflush(stdout);
  }
  for (auto& mesher : summary.mean)
    for (double& m : mesher) m /= static_cast<double>(frames);
  summary.seconds[0] = ours.seconds;
  summary.pentatopes = ours.pentatopes;
  summary.time_scale = ours.time_scale;
  summary.ok = true;
  if (print_frames)
    std::printf(
        "\nmesh4d, the whole cycle in 4D: %.1f s (%llu pentatopes); Mesh_3, frame by frame: "
        "%.1f s in all; ratio %.2f\n",
        ours.seconds, static_cast<unsigned long long>(ours.pentatopes), summary.seconds[1],
        ours.seconds / summary.seconds[1]);
  return summary;
}

void print_frames_summaries(const std::vector<std::pair<std::string, FramesSummary>>& rows,
                            double delta) {
  std::printf(
      "\nEvery frame's volume error per label against its voxels, δ = %g: mesh4d's 4D mesh (time "
      "scale chosen from the data, time caps) beside Mesh_3 frame by frame (facet distance 1)\n"
      "| image | time scale | mesh4d cavity mean / worst | mesh4d myocardium mean / worst | "
      "Mesh_3 cavity mean / worst | Mesh_3 myocardium mean / worst | mesh4d s (pentatopes) | "
      "Mesh_3 s |\n|---|---|---|---|---|---|---|---|\n",
      delta);
  for (const auto& [name, r] : rows) {
    if (!r.ok) continue;
    std::printf(
        "| %s | %g | %.1f %% / %+.1f %% | %.1f %% / %+.1f %% | %.1f %% / %+.1f %% | %.1f %% / "
        "%+.1f %% | %.1f (%llu) | %.1f |\n",
        name.c_str(), r.time_scale, r.mean[0][0], r.worst[0][0], r.mean[0][1], r.worst[0][1],
        r.mean[1][0], r.worst[1][0], r.mean[1][1], r.worst[1][1], r.seconds[0],
        static_cast<unsigned long long>(r.pentatopes), r.seconds[1]);
  }
  std::fflush(stdout);
}

}  // namespace mesh4d::bench
