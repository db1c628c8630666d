#include "refine/periodic_time.h"

#include "domain/periodic_time.h"
#include "domain/surface_oracle.h"

namespace mesh4d::refine {

RefineResult refine_periodic(const domain::LabelImage4& cycle, const RefineParams& params,
                             ProgressSink* sink, std::vector<std::string>* warnings) {
  const domain::TimePeriod period = domain::cycle_period(cycle);
  domain::LabelImage4 covering = domain::tile_cycle(cycle);
  // The covering's ends along t are closed too, but nothing there is meshed for the output.
  std::vector<std::string> closing = domain::validate_and_close(covering);
  domain::drop_time_padding_warnings(closing);
  warnings->insert(warnings->end(), closing.begin(), closing.end());
  const domain::SurfaceOracle oracle(covering);
  RefineParams periodic = params;
  periodic.period_start = period.start;
  periodic.period = period.length;
  return refine(oracle, periodic, sink);
}

}  // namespace mesh4d::refine
