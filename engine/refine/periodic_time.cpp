#include "refine/periodic_time.h"

#include "domain/periodic_time.h"
#include "domain/surface_oracle.h"

namespace mesh4d::refine {

RefineResult refine_periodic(const domain::LabelImage4& cycle, const RefineParams& params,
                             ProgressSink* sink, std::vector<std::string>* warnings) {
  const domain::TimePeriod period = domain::cycle_period(cycle);
  domain::LabelImage4 covering = domain::tile_cycle(cycle);
  // The covering's ends along t are closed too, but nothing there is meshed for the output:
  // only the closing of x, y and z concerns the user.
  for (std::string& w : domain::validate_and_close(covering))
    if (w.find("along t;") == std::string::npos) warnings->push_back(std::move(w));
  const domain::SurfaceOracle oracle(covering);
  RefineParams periodic = params;
  periodic.period_start = period.start;
  periodic.period = period.length;
  return refine(oracle, periodic, sink);
}

}  // namespace mesh4d::refine
