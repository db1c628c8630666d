// Mesh quality: the columns of the paper's Table 2 (counts, shortest edge, radius-edge ratio and
// normalized volume distributions), plus per-rule counts and time filled in by the refiner.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

struct Distribution {
  double min = 0;
  double max = 0;
  double mean = 0;
  double stddev = 0;  // population standard deviation
};

/// Counts per refinement rule R1..R5 (index 0..4).
using RuleCounts = std::array<std::uint64_t, 5>;

struct MeshStats {
  std::uint64_t vertices = 0;  // in periodic time, glued at the seam (not its twins)
  std::uint64_t pentatopes = 0;
  std::uint64_t boundary_tetrahedra = 0;
  double shortest_edge = 0;
  Distribution radius_edge_ratio;
  Distribution normalized_volume;
  /// normalized_volume_histogram[i] counts values in [i/n, (i+1)/n), the last bin including 1.
  std::vector<std::uint64_t> normalized_volume_histogram;
  RuleCounts insertions{};
  RuleCounts removals{};
  double elapsed_seconds = 0;
  /// How far the sag offset moved a boundary vertex off ∂Ω (refine/facet_sag.h), physical units;
  /// 0: every boundary vertex lies on ∂Ω. Set by the refiner, like the rule counts.
  double boundary_offset = 0;
};

inline constexpr int kHistogramBins = 20;

/// Measures every pentatope of the mesh (counts and distributions; rule counts and time are
/// left at zero for the caller), on up to `threads` threads (shares of at least 4,096
/// pentatopes). The counts, extremes and histogram are the same on any number of threads; the
/// means and deviations may differ in their last bits.
MeshStats compute_stats(const Mesh4& mesh, unsigned threads = 1);

}  // namespace mesh4d::mesh
