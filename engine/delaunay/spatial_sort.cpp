// CGAL's dD spatial sort on indices into the caller's points (traits in the SpatialSortingTraits_d
// form), in its own translation unit to keep CGAL's templates out of the rest of the engine.
#include "delaunay/spatial_sort.h"

#include <CGAL/spatial_sort.h>

#include <numeric>

namespace mesh4d::delaunay {
namespace {

struct IndexTraits {
  using Point_d = std::size_t;
  const Point4* points;

  struct Less_coordinate_d {
    const Point4* points;
    bool operator()(Point_d a, Point_d b, int axis) const {
      return points[a][axis] < points[b][axis];
    }
  };
  struct Point_dimension_d {
    int operator()(Point_d) const { return 4; }
  };
  struct Compute_coordinate_d {
    const Point4* points;
    double operator()(Point_d a, int axis) const { return points[a][axis]; }
  };
  Less_coordinate_d less_coordinate_d_object() const { return {points}; }
  Point_dimension_d point_dimension_d_object() const { return {}; }
  Compute_coordinate_d compute_coordinate_d_object() const { return {points}; }
};

}  // namespace

std::vector<std::size_t> spatial_order(std::span<const Point4> points) {
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  if (order.size() < 2) return order;
  // CGAL shuffles with a fixed-seed generator: the same batch always gets the same order.
  CGAL::spatial_sort(order.begin(), order.end(), IndexTraits{points.data()});
  return order;
}

}  // namespace mesh4d::delaunay
