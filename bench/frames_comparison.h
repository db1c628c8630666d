// refine_bench's comparison with what a user would otherwise do: the 4D mesh of a patient's
// whole cycle, as a job with `--delta` alone makes it, against each 3D frame meshed separately by
// CGAL Mesh_3 (mesh3_frames.h): times, and each frame's volume per label against the voxel
// volume.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::bench {

/// Per label (cavity, myocardium) and per mesher (mesh4d, Mesh_3): the mean |volume error| over
/// the frames and the error of largest magnitude, percent.
struct FramesSummary {
  bool ok = false;
  double mean[2][2] = {};   // [mesh4d, Mesh_3][label 1, 2]
  double worst[2][2] = {};  // signed
  double seconds[2] = {};   // the 4D run; Mesh_3's frames in all
  std::uint64_t pentatopes = 0;
  double time_scale = 0;
};

/// Meshes `image` both ways; prints the per-frame table when `print_frames`. Labels 1 and 2.
FramesSummary compare_with_mesh3_frames(const char* name, const domain::LabelImage4& image,
                                        double delta, bool print_frames);

/// One row per image: the mean and worst frame per label, mesh4d beside Mesh_3.
void print_frames_summaries(const std::vector<std::pair<std::string, FramesSummary>>& rows,
                            double delta);

}  // namespace mesh4d::bench
