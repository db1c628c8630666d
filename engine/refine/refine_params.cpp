#include "refine/refine_params.h"

#include <cmath>
#include <sstream>

namespace mesh4d::refine {
namespace {

void require(bool ok, const char* name, double value, const char* range) {
  if (ok) return;
  std::ostringstream s;
  s << "refinement parameter " << name << " = " << value << " is out of range: " << range;
  throw ParamError(s.str());
}

}  // namespace

void validate(const RefineParams& p) {
  require(std::isfinite(p.delta) && p.delta > 0, "delta", p.delta, "must be finite and > 0");
  // Below √2 no 4D Delaunay refinement can terminate (the regular pentatope has 0.63, but
  // refinement in practice cannot reach much below the values the paper reports, 1.5 to 2.2).
  require(std::isfinite(p.radius_edge_bound) && p.radius_edge_bound >= 1.0, "radius_edge_bound",
          p.radius_edge_bound, "must be finite and ≥ 1");
  require(std::isfinite(p.picking_ratio) && p.picking_ratio > 0 && p.picking_ratio < 1,
          "picking_ratio", p.picking_ratio, "must be in (0, 1)");
  require(p.picking_trials >= 1 && p.picking_trials <= 1000, "picking_trials",
          double(p.picking_trials), "must be in 1..1000");
  require(std::isfinite(p.sliver_bound) && p.sliver_bound >= 0 && p.sliver_bound < 1,
          "sliver_bound", p.sliver_bound, "must be in [0, 1)");
  require(std::isfinite(p.max_interior_radius) && p.max_interior_radius >= 0, "max_interior_radius",
          p.max_interior_radius, "must be finite and ≥ 0 (0: no bound)");
  require(std::isfinite(p.junction_spacing) && p.junction_spacing >= 0 && p.junction_spacing <= 1,
          "junction_spacing", p.junction_spacing, "must be in [0, 1] (0: off)");
  require(p.threads >= 1 && p.threads <= 1024, "threads", double(p.threads), "must be in 1..1024");
  require(std::isfinite(p.period) && p.period >= 0, "period", p.period,
          "must be finite and ≥ 0 (0: open time)");
  require(std::isfinite(p.period_start), "period_start", p.period_start, "must be finite");
  require(std::isfinite(p.period_margin) && p.period_margin >= 0 && p.period_margin <= p.period,
          "period_margin", p.period_margin, "must be in [0, period] (0: a whole period)");
  require(std::isfinite(p.period_trusted) && p.period_trusted >= 0 &&
              p.period_trusted <= (p.period_margin > 0 ? p.period_margin : p.period),
          "period_trusted", p.period_trusted, "must be in [0, period_margin] (0: half the margin)");
  require(p.vertex_budget >= 16, "vertex_budget", double(p.vertex_budget),
          "must be at least 16 (the box corners)");
}

}  // namespace mesh4d::refine
