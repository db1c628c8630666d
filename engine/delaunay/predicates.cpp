// Filtered exact predicates in four stages: a semi-static double filter (bound from column
// maxima), a dynamic double filter (bound from the absolute-value expression), interval
// arithmetic, and finally CGAL::Mpzf, exact on doubles.
//
// Why a dynamic bound as second stage: each determinant is evaluated once in double together with
// the same expression on absolute values (subtractions turned into additions). For an expression
// tree of depth d, the rounding error is at most γ_d = dε/(1-dε) times that absolute value (Higham,
// "Accuracy and Stability of Numerical Algorithms", §3.1). The bound is tight on well-shaped input,
// so the exact path runs only on near-degenerate configurations (grids, co-spherical points).
#include "delaunay/predicates.h"

#include <CGAL/Interval_nt.h>
#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cfloat>
#include <cmath>

#include "delaunay/double_double.h"
#include "delaunay/predicate_kernels.h"

namespace mesh4d::delaunay {
namespace {

using namespace detail;

// A double together with the value of the same expression on absolute values.
struct Bounded {
  double v;
  double a;
};
inline Bounded operator+(Bounded x, Bounded y) {
  return {x.v + y.v, x.a + y.a};
}
inline Bounded operator-(Bounded x, Bounded y) {
  return {x.v - y.v, x.a + y.a};
}
inline Bounded operator*(Bounded x, Bounded y) {
  return {x.v * y.v, x.a * y.a};
}

// Leaves are coordinate differences. The relative error model needs no underflow or overflow in
// products of up to six leaves: every non-zero leaf must lie in [1e-40, 1e40], else go exact.
constexpr double kLeafMin = 1e-40;
constexpr double kLeafMax = 1e40;
inline bool leaf_in_range(double d) {
  const double m = std::fabs(d);
  return m == 0.0 || (m > kLeafMin && m < kLeafMax);
}

// Error coefficients of stage 2 (depths in predicate_kernels.h). Two extra ε cover the rounding
// of the absolute evaluation itself and of the final product coefficient·a.
constexpr double kOrientCoef = (kOrientDepth + 2) * DBL_EPSILON / 2;
constexpr double kInsphereCoef = (kInsphereDepth + 2) * DBL_EPSILON / 2;

// det[p1-p0; p2-p0; p3-p0; p4-p0] with leaves made by `diff`.
template <class NT, class Diff>
NT orient_det(const Point4* const p[5], Diff diff) {
  NT m[4][4];
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) m[i][j] = diff((*p[i + 1])[j], (*p[0])[j]);
  return det4(m);
}

// Leaf makers for the two evaluation modes. The filtered one also reports leaves out of range.
struct FilterDiff {
  bool* in_range;
  Bounded operator()(double x, double y) const {
    const double d = x - y;
    *in_range = *in_range && leaf_in_range(d);
    return {d, std::fabs(d)};
  }
};
struct IntervalDiff {
  CGAL::Interval_nt<false> operator()(double x, double y) const {
    return CGAL::Interval_nt<false>(x) - CGAL::Interval_nt<false>(y);
  }
};
struct DoubleDoubleDiff {
  DoubleDouble operator()(double x, double y) const { return DoubleDouble::two_sum(x, -y); }
};
struct ExactDiff {
  CGAL::Mpzf operator()(double x, double y) const { return CGAL::Mpzf(x) - CGAL::Mpzf(y); }
};

inline int sign_of(const CGAL::Mpzf& x) {
  return static_cast<int>(CGAL::sign(x));
}

// Interval arithmetic decides what the double filter cannot but rounding never touched: on
// grid input every product of small integers is exact, so exact zeros come out as [0, 0]
// without the multiprecision path. Returns kUndecided when the interval straddles zero.
template <class Eval>
int interval_sign(Eval eval) {
  CGAL::Protect_FPU_rounding<true> rounding;
  const CGAL::Interval_nt<false> r = eval();
  if (r.inf() > 0) return 1;
  if (r.sup() < 0) return -1;
  if (r.inf() == 0 && r.sup() == 0) return 0;
  return kUndecided;
}

// Returns -1, 0, +1 when a filter decides the sign, or kUndecided when it cannot.
inline int filtered_sign(const Bounded& r, bool in_range, double coef) {
  if (!in_range) return kUndecided;
  const double bound = coef * r.a;
  if (r.v > bound) return 1;
  if (r.v < -bound) return -1;
  // Exactly zero only when every term is zero: a zero absolute sum means an exact zero.
  if (r.a == 0.0) return 0;
  return kUndecided;
}

int orient_semi_static(const Point4* const p[5]) {
  double m[4][4];
  double mx[4] = {0, 0, 0, 0};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      m[i][j] = (*p[i + 1])[j] - (*p[0])[j];
      mx[j] = std::max(mx[j], std::fabs(m[i][j]));
    }
  const double det = det4(m);
  const double bound = kOrientSemiCoef * mx[0] * mx[1] * mx[2] * mx[3];
  return semi_static_sign(det, bound, std::max(std::max(mx[0], mx[1]), std::max(mx[2], mx[3])));
}

// Stage 3: the same expression in double-double. Leaves are exact (two_sum), every operation has
// relative error ≤ DoubleDouble::kRelativeError, so the error is at most γ_depth of that unit
// times the absolute-value expression, which stage 2 computed (r.a, to within a relative 1e-13).
// Needs the stage-2 range guard (no underflow or overflow).
inline int double_double_sign(const DoubleDouble& r, double abs_bound, int depth) {
  const double bound = (depth + 2) * DoubleDouble::kRelativeError * abs_bound * (1 + 1e-12);
  const double v = r.hi + r.lo;
  if (v > bound) return 1;
  if (v < -bound) return -1;
  return kUndecided;
}

int orient4_of(const Point4* const p[5]) {
  auto& counters = predicate_counters();
  ++counters.orient_calls;
  const int fast = orient_semi_static(p);
  if (fast != kUndecided) return fast;
  ++counters.orient_dynamic;
  bool in_range = true;
  const Bounded r = orient_det<Bounded>(p, FilterDiff{&in_range});
  const int s = filtered_sign(r, in_range, kOrientCoef);
  if (s != kUndecided) return s;
  ++counters.orient_double_double;
  if (in_range) {
    const int sd =
        double_double_sign(orient_det<DoubleDouble>(p, DoubleDoubleDiff{}), r.a, kOrientDepth);
    if (sd != kUndecided) return sd;
  }
  const int si =
      interval_sign([&] { return orient_det<CGAL::Interval_nt<false>>(p, IntervalDiff{}); });
  if (si != kUndecided) return si;
  ++counters.orient_exact;
  return sign_of(orient_det<CGAL::Mpzf>(p, ExactDiff{}));
}

}  // namespace

PredicateCounters& predicate_counters() {
  thread_local PredicateCounters counters;
  return counters;
}

int orient4(const Point4& a, const Point4& b, const Point4& c, const Point4& d, const Point4& e) {
  const Point4* const p[5] = {&a, &b, &c, &d, &e};
  return orient4_of(p);
}

namespace {

// Stages 2 to 4 of in-sphere, for a call that stage 1 could not decide.
int insphere4_past_semi_static(const Point4* const s[5], const Point4& q) {
  auto& counters = predicate_counters();
  ++counters.insphere_dynamic;
  bool in_range = true;
  const Bounded r = insphere_det<Bounded>(s, q, FilterDiff{&in_range});
  const int sign = filtered_sign(r, in_range, kInsphereCoef);
  if (sign != kUndecided) return sign;
  ++counters.insphere_double_double;
  if (in_range) {
    const int sd = double_double_sign(insphere_det<DoubleDouble>(s, q, DoubleDoubleDiff{}), r.a,
                                      kInsphereDepth);
    if (sd != kUndecided) return sd;
  }
  const int si =
      interval_sign([&] { return insphere_det<CGAL::Interval_nt<false>>(s, q, IntervalDiff{}); });
  if (si != kUndecided) return si;
  ++counters.insphere_exact;
  return sign_of(insphere_det<CGAL::Mpzf>(s, q, ExactDiff{}));
}

// The symbolic tie-break of an exact zero (see insphere4_sos in the header).
int insphere4_tie_break(const Point4* const s[5], const VertexId s_ids[5], const Point4& q,
                        VertexId q_id);

}  // namespace

int insphere4(const Point4* const s[5], const Point4& q) {
  ++predicate_counters().insphere_calls;
  const int fast = insphere_semi_static(s, q);
  if (fast != kUndecided) return fast;
  return insphere4_past_semi_static(s, q);
}

int detail::insphere4_sos_past_semi_static(const Point4* const s[5], const VertexId s_ids[5],
                                           const Point4& q, VertexId q_id) {
  ++predicate_counters().insphere_calls;
  const int exact = insphere4_past_semi_static(s, q);
  if (exact != 0) return exact;
  return insphere4_tie_break(s, s_ids, q, q_id);
}

int insphere4_sos(const Point4* const s[5], const VertexId s_ids[5], const Point4& q,
                  VertexId q_id) {
  const int exact = insphere4(s, q);
  if (exact != 0) return exact;
  return insphere4_tie_break(s, s_ids, q, q_id);
}

namespace {

int insphere4_tie_break(const Point4* const s[5], const VertexId s_ids[5], const Point4& q,
                        VertexId q_id) {
  ++predicate_counters().insphere_ties;

  // Lifting point j to |p_j|² + ε_j adds ε_j · ∂det/∂w_j = ε_j · (-1)^j · orient4(the other five)
  // to the 6×6 lifted determinant of rows (s_0..s_4, q). The largest ε belongs to the largest id,
  // so the first non-zero cofactor in decreasing id order decides.
  const Point4* pts[6] = {s[0], s[1], s[2], s[3], s[4], &q};
  const VertexId ids[6] = {s_ids[0], s_ids[1], s_ids[2], s_ids[3], s_ids[4], q_id};
  int order[6] = {0, 1, 2, 3, 4, 5};
  for (int i = 1; i < 6; ++i)  // insertion sort, decreasing id
    for (int k = i; k > 0 && ids[order[k]] > ids[order[k - 1]]; --k)
      std::swap(order[k], order[k - 1]);

  for (int j : order) {
    const Point4* others[5];
    for (int k = 0, r = 0; k < 6; ++k)
      if (k != j) others[r++] = pts[k];
    const int o = orient4_of(others);
    if (o != 0) return (j % 2 == 0) ? o : -o;
  }
  // Unreachable for a simplex with orient4(s) > 0: the cofactor of q is that orientation.
  return 0;
}

}  // namespace

}  // namespace mesh4d::delaunay
