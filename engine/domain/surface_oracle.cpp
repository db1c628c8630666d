#include "domain/surface_oracle.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "domain/feature_transform.h"
#include "domain/label_pieces.h"

namespace mesh4d::domain {
namespace {

double norm(const Vec4& v) {
  return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
}

Point4 lerp(const Point4& a, const Point4& b, double s) {
  return {a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), a[2] + s * (b[2] - a[2]),
          a[3] + s * (b[3] - a[3])};
}

}  // namespace

SurfaceOracle::SurfaceOracle(const LabelImage4& image, const TimeCaps& caps, unsigned threads)
    : image_(image), feature_(feature_transform(image, threads)), uniform_(image, threads) {
  if (feature_.empty() || feature_[0] == kNoFeature)
    throw ImageError("image has a single label everywhere: there is no surface to mesh");
  const Vec4& s = image.spacing();
  voxel_size_ = std::max(std::max(s[0], s[1]), std::max(s[2], s[3]));
  min_spacing_ = std::min(std::min(s[0], s[1]), std::min(s[2], s[3]));
  cell_diagonal_ = norm(s);
  for (int corner = 0; corner < 16; ++corner)
    corner_offset_[corner] =
        image.linear_index(corner & 1, (corner >> 1) & 1, (corner >> 2) & 1, (corner >> 3) & 1);
  // A closed image (validate_and_close) has background all around: then every corner inside
  // the image of a cell on its border lies on that outer layer, so the cell is background
  // without a read of its corners (the circumcenters of big pentatopes outside the object fall
  // in such cells).
  border_background_ = true;
  const Dims4& d = image.dims();
  for (std::size_t t = 0; t < d[3] && border_background_; ++t)
    for (std::size_t z = 0; z < d[2] && border_background_; ++z)
      for (std::size_t y = 0; y < d[1] && border_background_; ++y) {
        const bool inner = t > 0 && t + 1 < d[3] && z > 0 && z + 1 < d[2] && y > 0 && y + 1 < d[1];
        for (std::size_t x = 0; x < d[0]; x += inner ? std::max<std::size_t>(d[0] - 1, 1) : 1)
          if (image.at(x, y, z, t) != 0) {
            border_background_ = false;
            break;
          }
      }
  const auto twin = [&](Label l) { return caps.is_ghost(l) ? caps.real_of[l] : Label{0}; };
  std::vector<Label> ranked;
  for (Label l : image.labels())
    if (twin(l) == 0) ranked.push_back(l);
  offset_ = label_offsets(ranked);
  const std::vector<Label> labels = image.labels();
  offset_.resize(std::max<std::size_t>(offset_.size(), labels.back() + 1u), 0.0);
  for (Label l : labels)
    if (twin(l) != 0) offset_[l] = offset(twin(l));
  real_of_ = caps.real_of;
  pieces_ = label_function_pieces(image, nullptr, threads);
}

Label SurfaceOracle::real_label(Label l) const {
  return l < real_of_.size() && real_of_[l] != 0 ? real_of_[l] : l;
}

std::vector<double> SurfaceOracle::label_offsets(const std::vector<Label>& labels) {
  std::vector<double> offset(labels.empty() ? 1u : labels.back() + 1u, 0.0);
  for (std::size_t r = 0; r < labels.size() && labels.size() > 1; ++r)
    offset[labels[r]] = kMaxLabelOffset * static_cast<double>(r) / (labels.size() - 1);
  return offset;
}

std::size_t SurfaceOracle::nearest_voxel(const Point4& x, Point4* center) const {
  const Vec4 u = image_.to_index(x);
  const Dims4& d = image_.dims();
  std::size_t c[4];
  for (int a = 0; a < 4; ++a)
    c[a] = static_cast<std::size_t>(std::clamp(std::round(u[a]), 0.0, double(d[a] - 1)));
  if (center) *center = image_.voxel_center(c[0], c[1], c[2], c[3]);
  return image_.linear_index(c[0], c[1], c[2], c[3]);
}

std::uint32_t SurfaceOracle::piece_at(const Point4& x, Label label) const {
  const std::uint32_t p = nearest_piece(x);
  return p != FacePieces::kNoPiece && pieces_.pieces[p].label == label ? p : FacePieces::kNoPiece;
}

std::uint32_t SurfaceOracle::nearest_piece(const Point4& x) const {
  return pieces_.piece[nearest_voxel(x, nullptr)];
}

Point4 SurfaceOracle::center_of(std::uint32_t voxel, std::uint32_t coordinates[4]) const {
  // 32-bit divisions: the feature transform's indices fit (it stores them in 32 bits).
  const Dims4& d = image_.dims();
  for (int a = 0; a < 4; ++a) {
    const auto size = static_cast<std::uint32_t>(d[a]);
    coordinates[a] = voxel % size;
    voxel /= size;
  }
  return image_.voxel_center(coordinates[0], coordinates[1], coordinates[2], coordinates[3]);
}

SurfaceOracle::PointFacts SurfaceOracle::facts(const Point4& x, Label label) const {
  PointFacts f;
  f.label = label;
  Point4 v;
  const std::size_t nearest = nearest_voxel(x, &v);
  f.surface_voxel = feature_[nearest];
  std::uint32_t fc[4];
  const Point4 s = center_of(f.surface_voxel, fc);
  // The nearest surface voxel to x is at least |v - s| - |x - v| away (s is nearest to v), and
  // every point of ∂Ω lies within one voxel-cell diagonal of a surface voxel.
  f.lower = std::max(0.0, distance(v, s) - distance(x, v) - cell_diagonal_);
  return f;
}

SurfaceOracle::LabelWeights SurfaceOracle::weights_at(const Point4& x) const {
  const Vec4 u = image_.to_index(x);
  const Dims4& d = image_.dims();
  LabelWeights w;
  // A cell or more beyond the outer voxel centers (also far away: a nearly flat pentatope's
  // circumcenter), every corner is outside: background, and no integer overflow below.
  bool far = false;
  for (int a = 0; a < 4; ++a) far = far || !(u[a] > -1 && u[a] < static_cast<double>(d[a]));
  if (far) {
    w.label[0] = 0;
    w.weight[0] = 1 + offset(0);
    w.count = 1;
    return w;
  }
  long base[4];
  double frac[4];
  bool interior = true;  // all 16 corners inside the image
  for (int a = 0; a < 4; ++a) {
    const double f = std::floor(u[a]);
    base[a] = static_cast<long>(f);
    frac[a] = u[a] - f;
    interior = interior && base[a] >= 0 && base[a] + 1 < static_cast<long>(d[a]);
  }
  Label corner_label[16];
  if (interior) {
    // The common case, and most queries fall in a cell of one label: no weights needed.
    const std::size_t first = image_.linear_index(base[0], base[1], base[2], base[3]);
    if (uniform_.uniform(first)) {
      w.label[0] = image_.at(first);
      w.weight[0] = 1 + offset(w.label[0]);
      w.count = 1;
      return w;
    }
    for (int corner = 0; corner < 16; ++corner)
      corner_label[corner] = image_.at(first + corner_offset_[corner]);
  } else if (border_background_) {
    // Every corner is background: outside the image, or on its outer layer of voxels.
    w.label[0] = 0;
    w.weight[0] = 1 + offset(0);
    w.count = 1;
    return w;
  } else {
    for (int corner = 0; corner < 16; ++corner) {
      bool in_image = true;
      std::size_t c[4];
      for (int a = 0; a < 4; ++a) {
        const long ci = base[a] + ((corner >> a) & 1);
        in_image = in_image && ci >= 0 && ci < static_cast<long>(d[a]);
        c[a] = static_cast<std::size_t>(ci);
      }
      corner_label[corner] = in_image ? image_.at(c[0], c[1], c[2], c[3]) : 0;
    }
  }
  return weights_in_cell(cell_labels(corner_label), frac);
}

SurfaceOracle::CellLabels SurfaceOracle::cell_labels(const Label corner_label[16]) {
  CellLabels cell;
  for (int corner = 0; corner < 16; ++corner) {
    const Label l = corner_label[corner];
    int k = 0;
    while (k < cell.count && cell.label[k] != l) ++k;
    if (k == cell.count) cell.label[cell.count++] = l;
    cell.slot[corner] = static_cast<std::uint8_t>(k);
  }
  return cell;
}

SurfaceOracle::LabelWeights SurfaceOracle::weights_in_cell(const CellLabels& cell,
                                                           const double frac[4]) const {
  // Corner weights as products of the (x, y) and (z, t) pairs: 24 products instead of 48. A
  // label whose corners all weigh 0 keeps weight 0 (plus its offset): it never wins, as the
  // weights sum to 1 and no offset reaches 1/16.
  const double g[4] = {1 - frac[0], 1 - frac[1], 1 - frac[2], 1 - frac[3]};
  const double xy[4] = {g[0] * g[1], frac[0] * g[1], g[0] * frac[1], frac[0] * frac[1]};
  const double zt[4] = {g[2] * g[3], frac[2] * g[3], g[2] * frac[3], frac[2] * frac[3]};
  LabelWeights w;
  w.count = cell.count;
  for (int k = 0; k < cell.count; ++k) w.label[k] = cell.label[k], w.weight[k] = 0;
  if (cell.count == 2) {
    // The common mixed cell: two sums kept in registers, each corner's product added to its
    // label's sum and 0 to the other's (exact), in corner order, so the same sums as below.
    double sum[2] = {0, 0};
    for (int corner = 0; corner < 16; ++corner) {
      const double product = xy[corner & 3] * zt[corner >> 2];
      const bool second = cell.slot[corner] != 0;
      sum[0] += second ? 0.0 : product;
      sum[1] += second ? product : 0.0;
    }
    w.weight[0] = sum[0];
    w.weight[1] = sum[1];
  } else {
    for (int corner = 0; corner < 16; ++corner)
      w.weight[cell.slot[corner]] += xy[corner & 3] * zt[corner >> 2];
  }
  for (int k = 0; k < w.count; ++k) w.weight[k] += offset(w.label[k]);
  return w;
}

Label SurfaceOracle::argmax(const LabelWeights& w) const {
  Label best = w.count ? w.label[0] : 0;
  double best_weight = w.count ? w.weight[0] : 0;
  for (int k = 1; k < w.count; ++k)
    if (w.weight[k] > best_weight || (w.weight[k] == best_weight && w.label[k] < best)) {
      best = w.label[k];
      best_weight = w.weight[k];
    }
  return best;
}

Label SurfaceOracle::label_at(const Point4& x) const {
  return argmax(weights_at(x));
}

double SurfaceOracle::cut_value(const Point4& x, Label a, Label b) const {
  const LabelWeights w = weights_at(x);
  double ia = offset(a), ib = offset(b);  // an absent label keeps its offset
  for (int k = 0; k < w.count; ++k) {
    if (w.label[k] == a) ia = w.weight[k];
    if (w.label[k] == b) ib = w.weight[k];
  }
  return ia - ib;
}

Vec4 SurfaceOracle::cut_gradient(const Point4& x, Label a, Label b) const {
  // Central differences at a tenth of a voxel: f is piecewise multilinear, so this is its exact
  // derivative except within that distance of a voxel-center hyperplane.
  Vec4 g;
  for (int axis = 0; axis < 4; ++axis) {
    const double h = 0.1 * image_.spacing()[axis];
    Point4 p = x, m = x;
    p[axis] += h;
    m[axis] -= h;
    g[axis] = (cut_value(p, a, b) - cut_value(m, a, b)) / (2 * h);
  }
  return g;
}

SurfacePoint SurfaceBracket::middle() const {
  return {lerp(a, b, 0.5), label_a, label_b};
}

SurfaceBracket SurfaceOracle::narrow(SurfaceBracket k, double tolerance) const {
  // Plain halving, on purpose: a secant step (regula falsi) needs ~10 evaluations instead of
  // ~35, but lands exactly on the root of the cut function, the same for every cell with the
  // same corner labels; its many exactly co-planar surface points gave degenerate pentatopes,
  // off-∂Ω boundary vertices and more pinches, on the hypersphere and on the patients.
  // Once both ends lie in one interior voxel cell, its labels are read once and each halving
  // only recomputes the weights (the same arithmetic as weights_at, so the same labels).
  const Dims4& d = image_.dims();
  CellLabels cell;
  double base[4];
  bool in_cell = false;
  const double tolerance2 = tolerance * tolerance;
  // 80 halvings take any segment inside the image below the spacing of doubles.
  for (int i = 0; i < 80; ++i) {
    const Point4 m = lerp(k.a, k.b, 0.5);
    if (m == k.a || m == k.b) break;
    double length2 = 0;
    for (int axis = 0; axis < 4; ++axis)
      length2 += (k.b[axis] - k.a[axis]) * (k.b[axis] - k.a[axis]);
    if (length2 < tolerance2) break;
    if (!in_cell) {
      const Vec4 ua = image_.to_index(k.a), ub = image_.to_index(k.b);
      in_cell = true;
      for (int axis = 0; axis < 4 && in_cell; ++axis) {
        base[axis] = std::floor(ua[axis]);
        in_cell = base[axis] == std::floor(ub[axis]) && base[axis] >= 0 &&
                  base[axis] + 1 < double(d[axis]);
      }
      if (in_cell) {
        const std::size_t first = image_.linear_index(
            static_cast<std::size_t>(base[0]), static_cast<std::size_t>(base[1]),
            static_cast<std::size_t>(base[2]), static_cast<std::size_t>(base[3]));
        Label corner_label[16];
        for (int corner = 0; corner < 16; ++corner)
          corner_label[corner] = image_.at(first + corner_offset_[corner]);
        cell = cell_labels(corner_label);
      }
    }
    Label lm;
    if (in_cell) {
      const Vec4 u = image_.to_index(m);
      const double frac[4] = {u[0] - base[0], u[1] - base[1], u[2] - base[2], u[3] - base[3]};
      lm = argmax(weights_in_cell(cell, frac));
    } else {
      lm = label_at(m);
    }
    if (lm == k.label_a) {
      k.a = m;
    } else {
      k.b = m;
      k.label_b = lm;
    }
  }
  return k;
}

std::optional<SurfacePoint> SurfaceOracle::first_crossing(const Point4& a, const Point4& b) const {
  const auto k = first_bracket(a, b, fine_tolerance());
  if (!k) return std::nullopt;
  return k->middle();
}

std::optional<SurfaceBracket> SurfaceOracle::first_bracket(
    const Point4& a, const Point4& b, double tolerance, const Label* label_a, const GiveUp* give_up,
    const WalkDismissal* walk_dismissal) const {
  const Label la = label_a ? *label_a : label_at(a);  // the caller may know it
  // Only the part of the segment within a cell of the voxel centers can see a label change:
  // beyond, every point is background. Clipping also keeps the walk short when an end is far
  // away (the circumcenter of a nearly flat pentatope).
  const Vec4 ua = image_.to_index(a), ub = image_.to_index(b);
  double t0 = 0, t1 = 1;
  for (int k = 0; k < 4; ++k) {
    const double lo = -1, hi = static_cast<double>(image_.dims()[k]), du = ub[k] - ua[k];
    if (du == 0) {
      if (!(ua[k] > lo && ua[k] < hi)) return std::nullopt;
      continue;
    }
    double enter = (lo - ua[k]) / du, leave = (hi - ua[k]) / du;
    if (enter > leave) std::swap(enter, leave);
    t0 = std::max(t0, enter);
    t1 = std::min(t1, leave);
  }
  if (!(t0 <= t1)) return std::nullopt;
  const Point4 start = t0 > 0 ? lerp(a, b, t0) : a;
  const Point4 end = t1 < 1 ? lerp(a, b, t1) : b;
  // Steps of at most half a cell along every axis (in index space: with the patients' 6 mm
  // slices and 1 mm frames, steps of half the smallest spacing were up to 6 times shorter): in
  // one step the piecewise-multilinear label function can change at most across one cell
  // boundary, so no thin feature is skipped over.
  double cells = 0;
  for (int k = 0; k < 4; ++k) cells = std::max(cells, (t1 - t0) * std::abs(ub[k] - ua[k]));
  const int steps = std::max(1, static_cast<int>(std::ceil(2 * cells)));
  Point4 previous = start;
  for (int i = 1; i <= steps; ++i) {
    const Point4 p = lerp(start, end, double(i) / steps);
    if (const Label lp = label_at(p); lp != la) return narrow({previous, p, la, lp}, tolerance);
    if (give_up && distance(give_up->from, p) > give_up->distance) return std::nullopt;
    // Every other sample: the crossing lies beyond p; the rest may all be dropped.
    if (walk_dismissal && i % 2 == 0 && walk_dismissal->dismissal->drops(p, walk_dismissal->end)) {
      *walk_dismissal->dropped = true;
      return std::nullopt;
    }
    previous = p;
  }
  return std::nullopt;
}

std::optional<SurfacePoint> SurfaceOracle::project_along(const Point4& seed,
                                                         const Vec4& normal) const {
  // The surface near seed along ±normal, within two voxels: the nearer crossing wins.
  const double reach = 2 * voxel_size_;
  const Point4 ahead{seed[0] + reach * normal[0], seed[1] + reach * normal[1],
                     seed[2] + reach * normal[2], seed[3] + reach * normal[3]};
  const Point4 behind{seed[0] - reach * normal[0], seed[1] - reach * normal[1],
                      seed[2] - reach * normal[2], seed[3] - reach * normal[3]};
  auto f = first_crossing(seed, ahead);
  auto g = first_crossing(seed, behind);
  if (f && g) return distance(f->point, seed) <= distance(g->point, seed) ? f : g;
  return f ? f : g;
}

SurfaceBracket SurfaceOracle::edge_bracket(const SurfaceBracket& edge, double tolerance) const {
  // A voxel center has its voxel's label (its own weight is 1), so the segment between two
  // neighboring voxel centers of different labels brackets a crossing already. On it only
  // those two voxels weigh (every other corner has a zero factor): I_a = 1 − s, I_b = s, and
  // the cut function f_ab = 1 − 2s + β_a − β_b is zero at s = (1 + β_a − β_b) / 2. A bracket
  // of `tolerance` around that point replaces a dozen halvings; closest_surface_bracket()
  // checks the labels at the ends of the one it returns.
  const double length = distance(edge.a, edge.b);
  const double root = 0.5 * (1 + offset(edge.label_a) - offset(edge.label_b));
  const double half = std::min(0.25, 0.5 * tolerance / length);
  return {lerp(edge.a, edge.b, root - half), lerp(edge.a, edge.b, root + half), edge.label_a,
          edge.label_b};
}

int SurfaceOracle::voxel_edges(const std::uint32_t sc[4], const Point4& center,
                               SurfaceBracket out[8]) const {
  const Dims4& d = image_.dims();
  const Label own = image_.at(image_.linear_index(sc[0], sc[1], sc[2], sc[3]));
  int count = 0;
  for (int a = 0; a < 4; ++a)
    for (int side = -1; side <= 1; side += 2) {
      std::size_t nc[4] = {sc[0], sc[1], sc[2], sc[3]};
      if ((side < 0 && nc[a] == 0) || (side > 0 && nc[a] + 1 >= d[a])) continue;
      nc[a] += side;
      const Label other = image_.at(image_.linear_index(nc[0], nc[1], nc[2], nc[3]));
      if (other == own) continue;
      Point4 n = center;
      n[a] += side * image_.spacing()[a];
      out[count++] = {center, n, own, other};
    }
  return count;
}

bool SurfaceOracle::cfp_candidates(const Point4& x, const PointFacts& known, CfpMode mode,
                                   double tolerance, std::vector<SurfaceBracket>& out,
                                   bool search_edges, const Dismissal* dismissal) const {
  // Start: the nearest surface voxel to the voxel nearest x.
  const Dims4& d = image_.dims();
  std::uint32_t sc[4];
  const Point4 center = center_of(known.surface_voxel, sc);

  // Candidate surface points: on the ray from x through that voxel (continued a voxel past it),
  // and between the voxel and each face neighbor of another label.
  std::vector<SurfaceBracket>& candidates = out;
  candidates.clear();
  SurfaceBracket edges[8];
  const int edge_count = voxel_edges(sc, center, edges);
  for (int i = 0; i < edge_count; ++i)
    edges[i] = search_edges ? narrow(edges[i], tolerance) : edge_bracket(edges[i], tolerance);
  // A dismissal is asked about where the candidates can lie, first before the ray's walk, then
  // about the rest of the walk as it goes, then before its crossing is halved. An edge's crossing
  // is edge_bracket's middle, or where a search finds it when rounding put that outside its
  // bracket: the cut function is linear along the edge (only its two voxels weigh), so within far
  // less than the bracket's length of it; edge brackets are asked about three times as long. A
  // ray's crossing lies between where its walk starts and ends (clipping to the image only shortens
  // it), and a bracket's middle between its ends, also after more halving. The ray mode's fallback
  // below needs no edges: with none, nothing is dismissed.
  bool edges_dropped = dismissal && edge_count > 0;
  for (int i = 0; i < edge_count && edges_dropped; ++i)
    edges_dropped =
        dismissal->drops(lerp(edges[i].a, edges[i].b, -1), lerp(edges[i].a, edges[i].b, 2));
  // The ray's crossing is ranked by its bracket's middle, which lies beyond the walk's last
  // sample of x's label: once a sample is farther from x than the nearest edge crossing (in
  // search_edges mode none is known), the ray cannot win and its walk stops there (ties go to
  // the ray). Its crossing matters only that near: that much of the ray is what a dismissal
  // is asked about.
  double nearest_edge = std::numeric_limits<double>::infinity();
  if (mode == CfpMode::ray && !search_edges && ray_give_up_)
    for (int i = 0; i < edge_count; ++i)
      nearest_edge = std::min(nearest_edge, distance(x, edges[i].middle().point));
  const GiveUp give_up{x, nearest_edge * (1 + 1e-9)};
  // No label changes closer to x than the feature transform's lower bound: rays from x start
  // their walk there (most of a far x's walk was in one label).
  const double lower = known.lower;
  const auto walk_start = [&](const Point4& end) {
    const double length = distance(x, end);
    return lower > 0 && lower < length ? lerp(x, end, lower / length) : x;
  };
  const double dist = distance(x, center);
  if (dist > 1e-9 * voxel_size_) {
    const Point4 end = lerp(x, center, (dist + 1.5 * voxel_size_) / dist);
    const double length = distance(x, end);
    const Point4 start = walk_start(end);
    // Its crossing lies beyond `lower`.
    const bool ray_loses = give_up.distance <= lower;
    const Point4 relevant_end =
        give_up.distance < length ? lerp(x, end, give_up.distance / length) : end;
    if (edges_dropped && (ray_loses || dismissal->drops(start, relevant_end))) return false;
    // As the walk goes, the rest of it is asked about again: a shorter segment is dropped more
    // often (most walks of dropped searches used to run to their crossing).
    bool walk_dropped = false;
    const WalkDismissal walk_dismissal{dismissal, relevant_end, &walk_dropped};
    // From x itself (x close to ∂Ω: the bound is 0), its label is known. Halving the walk's
    // bracket later in the same steps gives the same bracket.
    auto k = ray_loses ? std::nullopt
                       : first_bracket(
                             start, end,
                             edges_dropped ? std::numeric_limits<double>::infinity() : tolerance,
                             start == x ? &known.label : nullptr, &give_up,
                             edges_dropped ? &walk_dismissal : nullptr);
    if (walk_dropped) return false;
    if (k && edges_dropped) {
      if (dismissal->drops(k->a, k->b)) return false;
      *k = narrow(*k, tolerance);
    }
    if (k) candidates.push_back(*k);
  }
  if (edges_dropped && candidates.empty()) return false;
  candidates.insert(candidates.end(), edges, edges + edge_count);
  if (mode == CfpMode::descent || candidates.empty()) {
    // More starts: rays from x through the surface voxels around the nearest one (the zero set
    // near x is bumpy, and the closest bump need not be the one the nearest voxel points at).
    // The ray mode takes them only when its own starts found nothing.
    const auto ray = [&](const Point4& end) {
      const Point4 start = walk_start(end);
      return first_bracket(start, end, tolerance, start == x ? &known.label : nullptr);
    };
    for (int k = 0; k < 81; ++k) {
      std::size_t nc[4];
      bool ok = k != 40;  // 40 is the voxel itself
      for (int a = 0, r = k; a < 4 && ok; ++a, r /= 3) {
        const long c2 = static_cast<long>(sc[a]) + (r % 3) - 1;
        ok = c2 >= 0 && c2 < static_cast<long>(d[a]);
        nc[a] = static_cast<std::size_t>(c2);
      }
      if (!ok || !is_surface_voxel(image_, image_.linear_index(nc[0], nc[1], nc[2], nc[3])))
        continue;
      const Point4 other = image_.voxel_center(nc[0], nc[1], nc[2], nc[3]);
      const double dn = distance(x, other);
      if (dn <= 1e-9 * voxel_size_) continue;
      if (auto z = ray(lerp(x, other, (dn + 1.5 * voxel_size_) / dn))) candidates.push_back(*z);
    }
  }
  return true;
}

void SurfaceOracle::rank(const Point4& x, Label x_label, std::vector<SurfaceBracket>& candidates) {
  for (SurfaceBracket& k : candidates)
    if (k.label_b == x_label) std::swap(k.a, k.b), std::swap(k.label_a, k.label_b);
  std::stable_sort(candidates.begin(), candidates.end(), [&](const auto& a, const auto& b) {
    return distance(x, a.middle().point) < distance(x, b.middle().point);
  });
}

std::optional<SurfaceBracket> SurfaceOracle::closest_surface_bracket(const Point4& x,
                                                                     const PointFacts& known,
                                                                     const Dismissal* dismissal,
                                                                     bool* dropped) const {
  // Every candidate is bracketed coarsely, enough to rank them; pinpoint() narrows the one a
  // caller keeps: most of the ray mode's cost was halving candidates it then dropped.
  thread_local std::vector<SurfaceBracket> starts;
  const double tolerance = kRankTolerance * min_spacing_;
  const bool kept = cfp_candidates(x, known, CfpMode::ray, tolerance, starts, false, dismissal);
  if (dropped) *dropped = !kept;
  if (!kept || starts.empty()) return std::nullopt;
  rank(x, known.label, starts);
  const SurfaceBracket& k = starts.front();
  // A crossing computed on a voxel edge (its ends differ along one axis only; the ray's
  // seldom do) is checked; when rounding put it outside its bracket, every edge is searched.
  int axes = 0;
  for (int a = 0; a < 4; ++a) axes += k.a[a] != k.b[a];
  if (axes == 1 && (label_at(k.a) != k.label_a || label_at(k.b) != k.label_b))
    cfp_starts(x, known, CfpMode::ray, tolerance, starts, true);
  return starts.front();
}

SurfacePoint SurfaceOracle::pinpoint(const SurfaceBracket& k) const {
  return narrow(k, fine_tolerance()).middle();
}

SurfacePoint SurfaceOracle::closest_surface_point(const Point4& x, CfpMode mode) const {
  if (mode == CfpMode::ray) {
    const auto k = closest_surface_bracket(x);
    if (!k) return {x, label_at(x), label_at(x)};  // unreachable when validated
    return pinpoint(*k);
  }
  std::vector<SurfaceBracket> starts;
  cfp_starts(x, facts(x), mode, fine_tolerance(), starts);
  if (starts.empty()) return {x, label_at(x), label_at(x)};
  // The closest few starts are worth a descent: the interpolated surface of a voxelized shape
  // is bumpy at the voxel scale, so a single descent can stop on the wrong bump.
  SurfacePoint best = starts.front().middle();
  double best_distance = INFINITY;
  for (std::size_t i = 0; i < starts.size() && i < 6; ++i) {
    SurfacePoint z = starts[i].middle();
    refine_towards(x, z);
    const double dz = distance(x, z.point);
    if (dz < best_distance) best_distance = dz, best = z;
  }
  return best;
}

void SurfaceOracle::refine_towards(const Point4& x, SurfacePoint& z) const {
  // Projected descent: step along the tangent hyperplane towards x's foot point, back onto ∂Ω
  // along the normal; halve the step while it does not bring z closer to x.
  double current = distance(x, z.point);
  for (int iteration = 0; iteration < 30; ++iteration) {
    Vec4 g = cut_gradient(z.point, z.inner, z.outer);
    const double gn = norm(g);
    if (gn == 0) return;
    for (double& v : g) v /= gn;
    Vec4 r{x[0] - z.point[0], x[1] - z.point[1], x[2] - z.point[2], x[3] - z.point[3]};
    const double rn = r[0] * g[0] + r[1] * g[1] + r[2] * g[2] + r[3] * g[3];
    for (int a = 0; a < 4; ++a) r[a] -= rn * g[a];
    if (norm(r) < 1e-4 * voxel_size_) return;
    bool moved = false;
    for (double step = 1; step > 1.0 / 64 && !moved; step /= 2) {
      const Point4 seed{z.point[0] + step * r[0], z.point[1] + step * r[1],
                        z.point[2] + step * r[2], z.point[3] + step * r[3]};
      auto next = project_along(seed, g);
      if (!next) continue;
      if (next->inner != z.inner) std::swap(next->inner, next->outer);
      const double dn = distance(x, next->point);
      if (dn < current) {
        current = dn;
        z = *next;
        moved = true;
      }
    }
    if (!moved) return;
  }
}

}  // namespace mesh4d::domain
