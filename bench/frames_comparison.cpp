#include "frames_comparison.h"

#include <cmath>
#include <cstdio>

#include "bench_util.h"
#include "domain/surface_oracle.h"
#include "mesh/mesh_slice.h"
#include "mesh3_frames.h"
#include "refine/refiner.h"

namespace mesh4d::bench {
namespace {

constexpr std::size_t kMaxFrames = 64;

// What the 4D run sends back from its child process: its time and each frame's slice volumes.
struct SliceVolumes {
  double seconds = 0;
  std::uint64_t pentatopes = 0;
  double volume[kMaxFrames][2] = {};
  bool ok = false;
};

// The 4D refinement in a forked child (its memory its own, as in the other rows).
SliceVolumes refine_and_slice(const domain::LabelImage4& image, double delta) {
  const auto result = run_in_child<SliceVolumes>([&] {
    domain::LabelImage4 closed = image;
    domain::validate_and_close(closed);
    const domain::SurfaceOracle oracle(closed);
    refine::RefineParams params;
    params.delta = delta;
    refine::Refiner refiner(oracle, params);
    const auto r = refiner.run();
    SliceVolumes s;
    s.seconds = r.stats.elapsed_seconds;
    s.pentatopes = r.stats.pentatopes;
    for (std::size_t t = 0; t < image.dims()[3] && t < kMaxFrames; ++t) {
      // The frame's instant, in the original image's coordinates (padding keeps the origin).
      const auto v = mesh::slice_volumes(r.mesh, image.voxel_center(0, 0, 0, t)[3]);
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

void compare_with_mesh3_frames(const char* name, const domain::LabelImage4& image, double delta) {
  const auto& d = image.dims();
  const auto& s = image.spacing();
  const double voxel = s[0] * s[1] * s[2];
  const SliceVolumes ours = refine_and_slice(image, delta);
  if (!ours.ok) {
    std::printf("%s: the 4D run failed\n", name);
    return;
  }
  std::printf(
      "\n%s, δ = %g: the 4D mesh's cross-section at each frame against CGAL Mesh_3 on "
      "the frame alone (facet size δ, facet distance 1, radius-edge 2, perturb, exude); "
      "volume errors against the voxel volume\n",
      name, delta);
  std::printf(
      "| frame | voxel volume cavity / myocardium (mm³) | mesh4d error cavity / myocardium"
      " | Mesh_3 error cavity / myocardium | Mesh_3 tetrahedra | Mesh_3 s |\n"
      "|---|---|---|---|---|---|\n");
  double mesh3_seconds = 0, ours_abs = 0, mesh3_abs = 0;
  int samples = 0;
  for (std::size_t t = 0; t < d[3] && t < kMaxFrames; ++t) {
    double reference[2] = {0, 0};
    for (std::size_t z = 0; z < d[2]; ++z)
      for (std::size_t y = 0; y < d[1]; ++y)
        for (std::size_t x = 0; x < d[0]; ++x) {
          const auto l = image.at(x, y, z, t);
          if (l == 1 || l == 2) reference[l - 1] += voxel;
        }
    const FrameMesh m = mesh_frame_with_cgal(image, t, delta, 1.0);
    mesh3_seconds += m.seconds;
    double e_ours[2], e_cgal[2];
    for (int l = 0; l < 2; ++l) {
      e_ours[l] = percent_error(ours.volume[t][l], reference[l]);
      const auto it = m.volume.find(static_cast<domain::Label>(l + 1));
      e_cgal[l] = percent_error(it == m.volume.end() ? 0 : it->second, reference[l]);
      ours_abs += std::abs(e_ours[l]);
      mesh3_abs += std::abs(e_cgal[l]);
      ++samples;
    }
    std::printf("| %zu | %.0f / %.0f | %+.1f %% / %+.1f %% | %+.1f %% / %+.1f %% | %zu | %.2f |\n",
                t, reference[0], reference[1], e_ours[0], e_ours[1], e_cgal[0], e_cgal[1], m.cells,
                m.seconds);
    std::fflush(stdout);
  }
  std::printf(
      "\nmesh4d, the whole cycle in 4D: %.1f s (%llu pentatopes); Mesh_3, frame by frame: "
      "%.1f s in all; ratio %.2f. Mean |volume error|: mesh4d %.1f %%, Mesh_3 %.1f %%\n",
      ours.seconds, static_cast<unsigned long long>(ours.pentatopes), mesh3_seconds,
      ours.seconds / mesh3_seconds, ours_abs / samples, mesh3_abs / samples);
}

}  // namespace mesh4d::bench
