// refine_bench's comparison with what a user would otherwise do: the 4D mesh of a patient's
// whole cycle, as a job with `--delta` alone makes it (open time with its caps, and periodic
// time), against each 3D frame meshed separately by CGAL Mesh_3 (mesh3_frames.h): times, and
// each frame's volume per label against the voxel volume.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::bench {

/// The meshers compared: mesh4d in open time (time caps), mesh4d in periodic time, Mesh_3.
inline constexpr int kMeshers = 3;

/// Per label (cavity, myocardium) and per mesher: the mean |volume error| over the frames and
/// the error of largest magnitude, percent.
struct FramesSummary {
  bool ok = false;
  double mean[kMeshers][2] = {};   // [open, periodic, Mesh_3][label 1, 2]
  double worst[kMeshers][2] = {};  // signed
  double seconds[kMeshers] = {};   // the two 4D runs; Mesh_3's frames in all
  std::uint64_t pentatopes[2] = {};
  double time_scale[2] = {};
};

/// Meshes `image` both ways (mesh4d with or without its sag offset); prints the per-frame table
/// when `print_frames`. Labels 1 and 2.
FramesSummary compare_with_mesh3_frames(const char* name, const domain::LabelImage4& image,
                                        double delta, bool print_frames, bool sag_offset);

/// One row per image: the mean and worst frame per label, mesh4d beside Mesh_3.
void print_frames_summaries(const std::vector<std::pair<std::string, FramesSummary>>& rows,
                            double delta);

}  // namespace mesh4d::bench
