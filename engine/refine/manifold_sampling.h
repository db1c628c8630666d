// Manifold sampling (docs/refinement.md, "Closed, manifold region boundaries where labels
// meet"): where the manifold relabeling leaves a region's boundary failing at a vertex, ∂Ω is
// sampled there too coarsely for the restricted Delaunay triangulation to follow it (a neck, a
// saddle or a junction closer than Δ). A restricted facet of that region through the vertex is
// sampled at its surface center, the rules run, and the relabeling is tried again around the
// new pentatopes, in rounds; a round that does not lower the count samples every restricted
// facet through the failing vertices instead of one each. Where no facet gives a sample (a
// relabeling moved one side and the label function does not change across them, or every sample
// lies too close to a feature vertex), the search widens (manifold_sampling.cpp).
#pragma once

#include <functional>
#include <vector>

#include "refine/manifold_scan.h"
#include "refine/operation.h"
#include "refine/pinch_scan.h"

namespace mesh4d::refine {

class ManifoldSampling {
 public:
  /// Applies the rules until none applies.
  using Drain = std::function<void()>;
  /// Inserts surface points not within the spacing of a feature vertex; returns how many.
  using Insert = std::function<std::size_t(const std::vector<RepairPoint>&, double spacing)>;

  ManifoldSampling(RefinementState& state, const PinchScan& scan, Operation& operation,
                   unsigned workers)
      : state_(state), scan_(scan), operation_(operation), workers_(workers) {}

  struct Outcome {
    int rounds = 0;
    std::size_t points = 0;                  // inserted
    std::size_t moved = 0;                   // pentatopes the relabeling moved after the insertions
    std::vector<NonManifoldVertex> failing;  // left
  };
  /// Rounds until no (vertex, label) pair of `failing` is left, or a round inserts nothing.
  /// The first round also inserts `extra` (surface points another step asks for).
  Outcome run(std::vector<NonManifoldVertex> failing, const Drain& drain, const Insert& insert,
              std::vector<RepairPoint> extra = {});

 private:
  // The surface centers of f's label's restricted facets through f's vertex, none within
  // `spacing` of a feature vertex, appended to `out`: all, or only the one farthest from it.
  // When none gives a sample, those across which the label function does not change (a
  // relabeling moved one side) give ∂Ω's point nearest their Voronoi edges' middles.
  void samples_at(const NonManifoldVertex& f, double spacing, bool every,
                  std::vector<RepairPoint>& out) const;

  RefinementState& state_;
  const PinchScan& scan_;
  Operation& operation_;
  unsigned workers_;
};

}  // namespace mesh4d::refine
