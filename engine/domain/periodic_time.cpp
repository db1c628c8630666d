#include "domain/periodic_time.h"

#include <algorithm>
#include <cmath>

namespace mesh4d::domain {

double snap_time(double t) {
  // + 0.0 makes a −0.0 (a tiny negative time rounded to zero) +0.0.
  return std::nearbyint(t / kTimeQuantum) * kTimeQuantum + 0.0;
}

double TimePeriod::wrap(double t) const {
  double s = snap_time(t);
  // Both on the grid and far below 2⁵³ quanta: every step is exact.
  const double periods = std::floor((s - start) / length);
  s -= periods * length;
  // Rounding of the division can leave s one period off at the ends of the band.
  if (s < start) s += length;
  if (s >= start + length) s -= length;
  return s;
}

TimePeriod cycle_period(const LabelImage4& cycle) {
  const std::size_t frames = cycle.dims()[3];
  if (frames < 2)
    throw ImageError("periodic time needs at least two frames; this image has " +
                     std::to_string(frames));
  const double step = cycle.spacing()[3];
  TimePeriod period;
  period.start = snap_time(cycle.origin()[3] - step / 2);
  period.length = snap_time(static_cast<double>(frames) * step);
  return period;
}

LabelImage4 tile_cycle(const LabelImage4& cycle, std::size_t margin_frames) {
  const Dims4& d = cycle.dims();
  const std::size_t m = std::min(margin_frames, d[3]);
  Vec4 origin = cycle.origin();
  origin[3] -= static_cast<double>(m) * cycle.spacing()[3];
  LabelImage4 out({d[0], d[1], d[2], d[3] + 2 * m}, cycle.spacing(), origin);
  const std::size_t frame = d[0] * d[1] * d[2];
  for (std::size_t t = 0; t < d[3] + 2 * m; ++t) {
    const std::size_t source = (t + d[3] - m) % d[3];  // the cycle's frame at covering frame t
    for (std::size_t i = 0; i < frame; ++i)
      if (const Label l = cycle.at(source * frame + i)) out.set(t * frame + i, l);
  }
  return out;
}

void drop_time_padding_warnings(std::vector<std::string>& warnings) {
  std::erase_if(warnings,
                [](const std::string& w) { return w.find("along t;") != std::string::npos; });
}

}  // namespace mesh4d::domain
