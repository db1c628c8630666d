#include "refine/periodic_time.h"

#include <algorithm>
#include <cmath>

#include "domain/periodic_time.h"
#include "domain/surface_oracle.h"
#include "mesh/topology_certificate.h"

namespace mesh4d::refine {

std::size_t periodic_margin_frames(const domain::LabelImage4& cycle, double delta) {
  const double band = std::ceil(periodic_trusted_reach(delta) / cycle.spacing()[3] - 1e-9);
  return std::min(cycle.dims()[3], static_cast<std::size_t>(std::max(band, 1.0)) + 1);
}

RefineResult refine_periodic(const domain::LabelImage4& cycle, const RefineParams& params,
                             ProgressSink* sink, std::vector<std::string>* warnings) {
  const domain::TimePeriod period = domain::cycle_period(cycle);
  const std::size_t margin = periodic_margin_frames(cycle, params.delta);
  domain::LabelImage4 covering = domain::tile_cycle(cycle, margin);
  // The covering's ends along t are closed too, but nothing there is meshed for the output.
  std::vector<std::string> closing = domain::validate_and_close(covering);
  domain::drop_time_padding_warnings(closing);
  warnings->insert(warnings->end(), closing.begin(), closing.end());
  const domain::SurfaceOracle oracle(covering, {}, working_threads(params));
  RefineParams periodic = params;
  periodic.period_start = period.start;
  periodic.period = period.length;
  periodic.period_margin =
      margin == cycle.dims()[3] ? 0 : static_cast<double>(margin) * cycle.spacing()[3];
  periodic.period_trusted = std::min(periodic_trusted_reach(params.delta), period.length);
  RefineResult result = refine(oracle, periodic, sink);
  // What is left failing, counted on the glued cycle.
  std::size_t links = 0, pinched = 0;
  for (const mesh::LabelTopology& l : mesh::certify_topology(result.mesh).labels)
    links += l.non_manifold_vertices, pinched += l.non_manifold_triangles;
  result.non_manifold_left = links;
  for (std::string& w : manifold_warnings(links, pinched)) result.warnings.push_back(std::move(w));
  return result;
}

}  // namespace mesh4d::refine
