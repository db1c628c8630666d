// Exact geometric predicates of 4D Delaunay triangulation.
//
// Each predicate first evaluates its determinant in double with a per-call error bound (a
// dynamic filter: the same expression evaluated on absolute values bounds the rounding error)
// and falls back to exact arithmetic (CGAL::Mpzf, exact on doubles) only when the sign is not
// certain. Results are exact for every finite double input.
//
// Sign conventions (rows are points, first point subtracted):
//   orient4(a, b, c, d, e) = sign det[b-a; c-a; d-a; e-a]
//   insphere4(s, q) > 0  ⇔  q lies strictly inside the circumsphere of the simplex s,
//                          given orient4(s) > 0.
#pragma once

#include <cstdint>

#include "delaunay/point4.h"

namespace mesh4d::delaunay {

/// Exact sign (-1, 0, +1) of the orientation of five points.
int orient4(const Point4& a, const Point4& b, const Point4& c, const Point4& d, const Point4& e);

/// Exact sign of the in-sphere test of q against the positively oriented simplex s[0..4]:
/// +1 inside, 0 on, -1 outside the circumsphere.
int insphere4(const Point4* const s[5], const Point4& q);

/// In-sphere with a symbolic tie-break (simulation of simplicity on the lifted coordinate): equal
/// to insphere4 where that is non-zero; on a tie, as if each point p were lifted to |p|² + ε^(id),
/// where a larger id gets the larger perturbation. Never returns 0 for six distinct points with
/// orient4(s) > 0. A point that is exactly co-spherical with a simplex and newer (larger id) than
/// all its vertices is therefore outside.
int insphere4_sos(const Point4* const s[5], const VertexId s_ids[5], const Point4& q,
                  VertexId q_id);

/// How far down the filter stages calls went (per thread, since thread start). Benchmarks
/// report the double-double and multiprecision rates; tests check that degenerate input
/// really reaches those stages.
struct PredicateCounters {
  std::uint64_t orient_calls = 0;
  std::uint64_t orient_dynamic = 0;        // the semi-static filter failed
  std::uint64_t orient_double_double = 0;  // both double filters failed
  std::uint64_t orient_exact = 0;          // double-double and intervals failed too: Mpzf
  std::uint64_t insphere_calls = 0;
  std::uint64_t insphere_dynamic = 0;
  std::uint64_t insphere_double_double = 0;
  std::uint64_t insphere_exact = 0;
  std::uint64_t insphere_ties = 0;  // exact zero, resolved symbolically
};
PredicateCounters& predicate_counters();

}  // namespace mesh4d::delaunay
