// Solves the 4×4 system A x = b by Cramer's rule through the adjugate, its cofactors built from
// the twelve 2×2 minors of rows (0, 1) and (2, 3): no branch and one division. Shared by
// circumcenter() and circumballs4() (one pentatope, or one lane of four), which must compute
// the same bits.
#pragma once

namespace mesh4d::delaunay {

/// m(i, j) reads A's entry; sets *det and x = adj(A) b / det (not finite when det is 0).
template <class Entry>
[[gnu::always_inline]] inline void cramer4(const Entry& m, const double b[4], double* det,
                                           double x[4]) {
  const double s0 = m(0, 0) * m(1, 1) - m(1, 0) * m(0, 1);
  const double s1 = m(0, 0) * m(1, 2) - m(1, 0) * m(0, 2);
  const double s2 = m(0, 0) * m(1, 3) - m(1, 0) * m(0, 3);
  const double s3 = m(0, 1) * m(1, 2) - m(1, 1) * m(0, 2);
  const double s4 = m(0, 1) * m(1, 3) - m(1, 1) * m(0, 3);
  const double s5 = m(0, 2) * m(1, 3) - m(1, 2) * m(0, 3);
  const double c5 = m(2, 2) * m(3, 3) - m(3, 2) * m(2, 3);
  const double c4 = m(2, 1) * m(3, 3) - m(3, 1) * m(2, 3);
  const double c3 = m(2, 1) * m(3, 2) - m(3, 1) * m(2, 2);
  const double c2 = m(2, 0) * m(3, 3) - m(3, 0) * m(2, 3);
  const double c1 = m(2, 0) * m(3, 2) - m(3, 0) * m(2, 2);
  const double c0 = m(2, 0) * m(3, 1) - m(3, 0) * m(2, 1);
  *det = s0 * c5 - s1 * c4 + s2 * c3 + s3 * c2 - s4 * c1 + s5 * c0;
  // Row i of the adjugate, times b.
  const double adj_b[4] = {(m(1, 1) * c5 - m(1, 2) * c4 + m(1, 3) * c3) * b[0] +
                               (-m(0, 1) * c5 + m(0, 2) * c4 - m(0, 3) * c3) * b[1] +
                               (m(3, 1) * s5 - m(3, 2) * s4 + m(3, 3) * s3) * b[2] +
                               (-m(2, 1) * s5 + m(2, 2) * s4 - m(2, 3) * s3) * b[3],
                           (-m(1, 0) * c5 + m(1, 2) * c2 - m(1, 3) * c1) * b[0] +
                               (m(0, 0) * c5 - m(0, 2) * c2 + m(0, 3) * c1) * b[1] +
                               (-m(3, 0) * s5 + m(3, 2) * s2 - m(3, 3) * s1) * b[2] +
                               (m(2, 0) * s5 - m(2, 2) * s2 + m(2, 3) * s1) * b[3],
                           (m(1, 0) * c4 - m(1, 1) * c2 + m(1, 3) * c0) * b[0] +
                               (-m(0, 0) * c4 + m(0, 1) * c2 - m(0, 3) * c0) * b[1] +
                               (m(3, 0) * s4 - m(3, 1) * s2 + m(3, 3) * s0) * b[2] +
                               (-m(2, 0) * s4 + m(2, 1) * s2 - m(2, 3) * s0) * b[3],
                           (-m(1, 0) * c3 + m(1, 1) * c1 - m(1, 2) * c0) * b[0] +
                               (m(0, 0) * c3 - m(0, 1) * c1 + m(0, 2) * c0) * b[1] +
                               (-m(3, 0) * s3 + m(3, 1) * s1 - m(3, 2) * s0) * b[2] +
                               (m(2, 0) * s3 - m(2, 1) * s1 + m(2, 2) * s0) * b[3]};
  const double inverse = 1 / *det;
  for (int i = 0; i < 4; ++i) x[i] = adj_b[i] * inverse;
}

}  // namespace mesh4d::delaunay
