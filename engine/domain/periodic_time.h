// Periodic time (docs/algorithm.md, "Periodic time"). A cardiac cycle's frame after the last is
// its first: the domain is Ω over a circle of time of length T = frames × time scale. It is
// meshed in the 3-sheeted covering along t, as CGAL's periodic triangulations do in space: the
// cycle tiled three times, every point inserted with its copies one period below and above, so
// that the point set, and with it the Delaunay triangulation near the middle sheet, is
// invariant under a shift by T. The middle sheet's pentatopes are the mesh.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "domain/label_image.h"

namespace mesh4d::domain {

struct TimePeriod {
  double start = 0;   // the seam: half a frame before the first frame
  double length = 0;  // T; 0: time is open
  bool periodic() const { return length > 0; }
  /// t on the grid of kTimeQuantum, moved by whole periods into [start, start + length): on
  /// that grid t ± T is exact, so the copies of a point are exact translates.
  double wrap(double t) const;
};

/// The grid of times in a periodic covering (physical units): 2⁻³⁰, far below any spacing.
inline constexpr double kTimeQuantum = 0x1p-30;
/// t rounded to the nearest multiple of kTimeQuantum.
double snap_time(double t);

/// The period of `cycle`: from half a frame before its first frame to half a frame past its
/// last. Throws ImageError for fewer than two frames (nothing to be periodic in).
TimePeriod cycle_period(const LabelImage4& cycle);

/// The covering: `cycle` where it lies, with its last `margin_frames` frames before it and its
/// first ones after it (at most a whole copy on each side: the cycle tiled three times, the
/// default).
LabelImage4 tile_cycle(const LabelImage4& cycle, std::size_t margin_frames = SIZE_MAX);

/// Drops validate_and_close's warnings about padding along t: a cycle has no ends in time to
/// close, so they do not concern its user.
void drop_time_padding_warnings(std::vector<std::string>& warnings);

}  // namespace mesh4d::domain
