#include "refine/frame_volume_fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "mesh/mesh_slice.h"
#include "refine/guarded_moves.h"
#include "support/parallel_parts.h"

namespace mesh4d::refine {

namespace {

constexpr std::size_t kMaxRounds = 4;
// Every section within this share of its voxels ends the fit: a third of what a pipeline is
// promised (3 %), and each round more costs the guard's checks again.
constexpr double kEnough = 1e-2;
// A round that takes less than this share off the sections' summed error is the last.
constexpr double kLeastGain = 0.1;
constexpr double kSmallestMove = 0.02;   // of the largest move
constexpr std::size_t kMinShare = 4096;  // boundary tetrahedra per thread, at least
constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();

// The frames fitted and how a time falls between them: in periodic time the frames within the
// period, the last one next to the first; in open time every frame, a time past the ends
// counting as its end frame.
struct Frames {
  std::vector<std::size_t> index;  // the image's frame of each
  std::vector<double> times;       // ascending
  double first = 0, step = 1, period = 0;

  // The two frames whose hat functions are non-zero at t, and their weights.
  std::array<std::pair<std::size_t, double>, 2> hat(double t) const {
    const std::size_t n = times.size();
    double x = (t - first) / step;
    if (period > 0) {
      x = std::fmod(x, static_cast<double>(n));
      if (x < 0) x += static_cast<double>(n);
    } else {
      x = std::clamp(x, 0.0, static_cast<double>(n - 1));
    }
    const auto f = std::min(static_cast<std::size_t>(x), n - 1);
    const double w = x - static_cast<double>(f);
    return {{{f, 1 - w}, {period > 0 ? (f + 1) % n : std::min(f + 1, n - 1), w}}};
  }
};

Frames frames_of(const domain::LabelImage4& image, const mesh::Mesh4& mesh) {
  Frames out;
  out.step = image.spacing()[3];
  out.period = mesh.period;
  for (std::size_t t = 0; t < image.dims()[3]; ++t) {
    const double time = image.voxel_center(0, 0, 0, t)[3];
    if (mesh.periodic() && (time < mesh.period_start || time >= mesh.period_start + mesh.period))
      continue;
    out.index.push_back(t);
    out.times.push_back(time);
  }
  if (!out.times.empty()) out.first = out.times.front();
  return out;
}

// Real labels numbered 0.. for the unknowns; the outside has none.
struct Labels {
  std::vector<std::uint32_t> slot;  // by label: its number, or kNone
  std::size_t count = 0;
};

Labels labels_of(const domain::SurfaceOracle& oracle) {
  Labels out;
  const std::vector<domain::Label> present = oracle.image().labels();
  const domain::Label top = present.empty() ? 0 : *std::max_element(present.begin(), present.end());
  out.slot.assign(std::size_t{top} + 1, kNone);
  for (domain::Label l : present) {
    const domain::Label r = oracle.real_label(l);
    if (r == 0 || out.slot[r] != kNone) continue;
    out.slot[r] = static_cast<std::uint32_t>(out.count++);
  }
  return out;
}

// A corner of a facet's section: on the edge from vertex a to b, at b's share s.
struct Corner {
  std::array<double, 3> x;
  std::uint32_t a, b;
  double s;
};

// The section of tetrahedron `v` by the hyperplane t = time, as triangles of corners (none, one
// or two), each corner on an edge that crosses the plane (an endpoint on it counts as above).
std::vector<std::array<Corner, 3>> section(const mesh::Mesh4& mesh,
                                           const std::array<std::uint32_t, 4>& v, double time) {
  std::array<std::uint32_t, 4> below{}, above{};
  int nb = 0, na = 0;
  for (std::uint32_t w : v) (mesh.vertices[w][3] < time ? below[nb++] : above[na++]) = w;
  const auto corner = [&](std::uint32_t lo, std::uint32_t hi) {
    const Point4& p = mesh.vertices[lo];
    const Point4& q = mesh.vertices[hi];
    const double s = (time - p[3]) / (q[3] - p[3]);
    return Corner{
        {p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1]), p[2] + s * (q[2] - p[2])}, lo, hi, s};
  };
  if (nb == 1 || na == 1) {
    const bool one_below = nb == 1;
    const std::uint32_t apex = one_below ? below[0] : above[0];
    const auto& rest = one_below ? above : below;
    std::array<Corner, 3> t{};
    for (int i = 0; i < 3; ++i) t[i] = one_below ? corner(apex, rest[i]) : corner(rest[i], apex);
    return {t};
  }
  if (nb == 2) {
    const Corner ac = corner(below[0], above[0]), ad = corner(below[0], above[1]),
                 bd = corner(below[1], above[1]), bc = corner(below[1], above[0]);
    return {{ac, ad, bd}, {ac, bd, bc}};
  }
  return {};
}

double area(const std::array<Corner, 3>& t) {
  const auto& a = t[0].x;
  const auto& b = t[1].x;
  const auto& c = t[2].x;
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                       u[0] * w[1] - u[1] * w[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// Solves a x = b by Gaussian elimination with partial pivoting; an unknown whose pivot
// vanishes (a section no mover reaches) stays 0.
std::vector<double> solve(std::vector<double> a, std::vector<double> b, std::size_t n) {
  double scale = 0;
  for (double v : a) scale = std::max(scale, std::abs(v));
  const double tiny = 1e-12 * scale;
  std::vector<std::size_t> pivot_col(n, kNone);
  std::vector<char> used(n, 0);
  for (std::size_t col = 0, row = 0; col < n && row < n; ++col) {
    std::size_t best = row;
    for (std::size_t r = row; r < n; ++r)
      if (std::abs(a[r * n + col]) > std::abs(a[best * n + col])) best = r;
    if (!(std::abs(a[best * n + col]) > tiny)) continue;
    if (best != row) {
      for (std::size_t c = 0; c < n; ++c) std::swap(a[best * n + c], a[row * n + c]);
      std::swap(b[best], b[row]);
    }
    for (std::size_t r = row + 1; r < n; ++r) {
      const double k = a[r * n + col] / a[row * n + col];
      if (k == 0) continue;
      for (std::size_t c = col; c < n; ++c) a[r * n + c] -= k * a[row * n + c];
      b[r] -= k * b[row];
    }
    pivot_col[row++] = col;
    used[col] = 1;
  }
  std::vector<double> x(n, 0);
  for (std::size_t row = n; row-- > 0;) {
    const std::size_t col = pivot_col[row];
    if (col == kNone) continue;
    double s = b[row];
    for (std::size_t c = col + 1; c < n; ++c) s -= a[row * n + c] * x[c];
    x[col] = s / a[row * n + col];
  }
  return x;
}

// The least-squares form of J μ = r with a penalty on μ's jumps between neighbouring frames of
// a label (the last next to the first in periodic time): JᵀJ + α DᵀD. A vertex between two
// frames moves by their μs' blend, so μ alternating from frame to frame moves hardly anything
// where the vertices lie midway, and J alone leaves that mode free; the penalty holds it.
constexpr double kJumpPenalty = 1e-3;  // α, relative to the mean diagonal of JᵀJ

std::vector<double> regularized(const std::vector<double>& j, std::size_t n, std::size_t nf,
                                bool periodic) {
  std::vector<double> a(n * n, 0);
  for (std::size_t r = 0; r < n; ++r)
    for (std::size_t k = 0; k < n; ++k) {
      const double jr = j[r * n + k];
      if (jr == 0) continue;
      for (std::size_t c = 0; c < n; ++c) a[k * n + c] += jr * j[r * n + c];
    }
  double diagonal = 0;
  for (std::size_t k = 0; k < n; ++k) diagonal += a[k * n + k];
  const double alpha = kJumpPenalty * diagonal / static_cast<double>(n);
  for (std::size_t base = 0; base < n; base += nf)
    for (std::size_t f = 0; f < nf; ++f) {
      if (f + 1 == nf && !(periodic && nf > 2)) continue;
      const std::size_t p = base + f, q = base + (f + 1) % nf;
      a[p * n + p] += alpha, a[q * n + q] += alpha;
      a[p * n + q] -= alpha, a[q * n + p] -= alpha;
    }
  return a;
}

std::vector<double> normal_rhs(const std::vector<double>& j, const std::vector<double>& r,
                               std::size_t n) {
  std::vector<double> b(n, 0);
  for (std::size_t row = 0; row < n; ++row)
    if (r[row] != 0)
      for (std::size_t c = 0; c < n; ++c) b[c] += j[row * n + c] * r[row];
  return b;
}

// The fit's state: the sections' unknowns (a label's μ at a frame), their voxels, and the movers'
// directions and moves so far.
class FrameFit {
  // A mover's share of one section (frame), in volume per unit of its move.
  struct Share {
    std::uint32_t mover, frame;
    double volume;
  };

 public:
  FrameFit(mesh::Mesh4& mesh, const domain::SurfaceOracle& oracle, const InterfaceVertices& movers,
           unsigned threads)
      : mesh_(mesh),
        oracle_(oracle),
        movers_(movers),
        frames_(frames_of(oracle.image(), mesh)),
        labels_(labels_of(oracle)),
        nf_(frames_.times.size()),
        n_(labels_.count * nf_) {
    count_voxels(threads);
    choose_directions();
    find_reach();
  }

  std::size_t unknowns() const { return n_; }
  std::size_t sections() const {
    return static_cast<std::size_t>(
        std::count_if(target_.begin(), target_.end(), [](double t) { return t > 0; }));
  }

  // Each section's volume in the mesh now.
  std::vector<double> measure(unsigned threads) const {
    std::vector<double> volume(n_, 0);
    const auto sections = mesh::slice_volumes(mesh_, frames_.times, threads);
    for (std::size_t f = 0; f < nf_; ++f)
      for (const auto& [l, v] : sections[f])
        if (const std::uint32_t u = unknown(l, f); u != kNone) volume[u] += v;
    return volume;
  }

  // The sections' relative errors, summed in magnitude.
  double total_error(const std::vector<double>& volume) const {
    double sum = 0;
    for (std::size_t u = 0; u < n_; ++u)
      if (target_[u] > 0) sum += std::abs(volume[u] / target_[u] - 1);
    return sum;
  }

  // The relative error of largest magnitude.
  double worst(const std::vector<double>& volume) const {
    double w = 0;
    for (std::size_t u = 0; u < n_; ++u)
      if (target_[u] > 0 && std::abs(volume[u] / target_[u] - 1) > std::abs(w))
        w = volume[u] / target_[u] - 1;
    return w;
  }

  // Each mover's share of the interface's sections at each frame: its hat function integrated
  // over them, by how much the section's volume grows per unit of its move. The facets are cut
  // on the job's threads, each part a range of them, and the parts are read in order: the
  // shares come in facet order on any number of threads. (They are not joined into one list: a
  // copy on one thread.)
  void measure_shares(unsigned threads) {
    const std::size_t nb = mesh_.boundary.size();
    const unsigned parts = support::parts_for(nb, kMinShare, threads);
    shares_.assign(parts, {});
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(nb, part, parts);
      for (std::size_t i = begin; i < end; ++i) cut_facet(mesh_.boundary[i], shares_[part]);
    });
  }

  // J[(l, f), (m, g)]: how the section of l at frame f grows with μ of m at frame g, through the
  // movers' shares, each weighed by how much of its last move the guard let it make: where the
  // guard holds a region's vertices back, μ grows until the others make up for them.
  std::vector<double> jacobian() const {
    std::vector<double> j(n_ * n_, 0);
    for (const auto& part : shares_)
      for (const Share& s : part) {
        const Reach& r = reach_[s.mover];
        const double w = s.volume * mobility_[s.mover];
        if (w == 0) continue;
        for (int p = 0; p < 2; ++p) {
          if (r.first_row[p] == kNone) continue;
          double* row = &j[(std::size_t{r.first_row[p]} + s.frame) * n_];
          for (int q = 0; q < 2; ++q)
            for (const auto& [col, h] : r.columns[q])
              if (col != kNone && h != 0) row[col] += (p == q ? 1 : -1) * w * h;
        }
      }
    return j;
  }

  // μ for the sections' shortfalls under J, in the penalized least-squares form.
  std::vector<double> solve_for(const std::vector<double>& j,
                                const std::vector<double>& volume) const {
    std::vector<double> rhs(n_, 0);
    for (std::size_t u = 0; u < n_; ++u)
      if (target_[u] > 0) rhs[u] = target_[u] - volume[u];
    return solve(regularized(j, n_, nf_, mesh_.periodic()), normal_rhs(j, rhs, n_), n_);
  }

  // Moves the movers by μ, guarded; false when none would move.
  bool move(const std::vector<double>& mu, const RefineParams& params) {
    std::vector<Point4> offset(mesh_.vertices.size(), Point4{});
    std::vector<std::uint32_t> moving;
    std::vector<double> wanted(movers_.ids.size(), 0);
    for (std::uint32_t i = 0; i < movers_.ids.size(); ++i) {
      if (mover_of_[movers_.ids[i]] != i) continue;
      const auto& side = movers_.sides[i];
      double d = 0;
      for (const auto& [g, h] : frames_.hat(mesh_.vertices[movers_.ids[i]][3])) {
        const std::uint32_t a = unknown(side[0], g), c = unknown(side[1], g);
        d += h * ((a == kNone ? 0 : mu[a]) - (c == kNone ? 0 : mu[c]));
      }
      // Within half a voxel of where the sag offset left it, whatever μ asks.
      d = std::clamp(moved_[i] + d, -cap_, cap_) - moved_[i];
      // A hundredth of a voxel changes no section by much, and every mover costs the guard the
      // checks of its pentatopes.
      if (std::abs(d) < kSmallestMove * cap_) continue;
      wanted[i] = d;
      for (int a = 0; a < 4; ++a) offset[movers_.ids[i]][a] = d * direction_[i][a];
      moving.push_back(movers_.ids[i]);
    }
    if (moving.empty()) return false;
    const std::vector<Point4> now = mesh_.vertices;
    const std::vector<double> scale =
        move_guarded(mesh_, now, movers_.glued, offset, moving, nullptr, params).scale;
    for (std::uint32_t i = 0; i < movers_.ids.size(); ++i)
      if (wanted[i] != 0) {
        moved_[i] += scale[movers_.ids[i]] * wanted[i];
        mobility_[i] = scale[movers_.ids[i]];
      }
    return true;
  }

 private:
  std::uint32_t unknown(domain::Label l, std::size_t f) const {
    const domain::Label r = l == 0 ? 0 : oracle_.real_label(l);
    return r == 0 || r >= labels_.slot.size() || labels_.slot[r] == kNone
               ? kNone
               : static_cast<std::uint32_t>(labels_.slot[r] * nf_ + f);
  }

  // The shares one interface facet gives its movers at the frames it spans.
  void cut_facet(const mesh::BoundaryTetrahedron& b, std::vector<Share>& out) const {
    if (!(b.outer == 0 || b.inner > b.outer)) return;  // each interface facet once
    if (oracle_.real_label(b.inner) == oracle_.real_label(b.outer)) return;  // a cap
    const auto add = [&](std::uint32_t vertex, std::uint32_t f, double w) {
      const std::uint32_t i = mover_of_[movers_.glued[vertex]];
      if (i != kNone && w != 0) out.push_back({i, f, w});
    };
    double lo = std::numeric_limits<double>::infinity(), hi = -lo;
    for (std::uint32_t v : b.vertices) {
      lo = std::min(lo, mesh_.vertices[v][3]);
      hi = std::max(hi, mesh_.vertices[v][3]);
    }
    // In periodic time a facet past the period's end is cut at the frames one period on.
    for (int shift = 0; shift < (mesh_.periodic() ? 2 : 1); ++shift) {
      const double offset = shift * mesh_.period;
      auto f = static_cast<std::uint32_t>(
          std::upper_bound(frames_.times.begin(), frames_.times.end(), lo - offset) -
          frames_.times.begin());
      for (; f < nf_ && frames_.times[f] + offset <= hi; ++f)
        for (const auto& tri : section(mesh_, b.vertices, frames_.times[f] + offset)) {
          const double share = area(tri) / 3;
          for (const Corner& c : tri) add(c.a, f, share * (1 - c.s)), add(c.b, f, share * c.s);
        }
    }
  }

  // The frames on the job's threads: a frame's sections are its own unknowns, each summed in
  // voxel order as on one thread.
  void count_voxels(unsigned threads) {
    const domain::LabelImage4& image = oracle_.image();
    const auto& s = image.spacing();
    const double voxel3 = s[0] * s[1] * s[2];
    const std::size_t per_frame = image.dims()[0] * image.dims()[1] * image.dims()[2];
    target_.assign(n_, 0);
    const unsigned parts = support::parts_for(nf_, 1, threads);
    support::run_parts(parts, [&](unsigned part) {
      const auto [begin, end] = support::part_range(nf_, part, parts);
      for (std::size_t f = begin; f < end; ++f) {
        const std::size_t base = frames_.index[f] * per_frame;
        for (std::size_t i = 0; i < per_frame; ++i)
          if (const domain::Label l = image.at(base + i); l != 0)
            if (const std::uint32_t u = unknown(l, f); u != kNone) target_[u] += voxel3;
      }
    });
    cap_ = 0.5 * std::min({s[0], s[1], s[2]});
  }

  void choose_directions() {
    mover_of_.assign(mesh_.vertices.size(), kNone);
    direction_.assign(movers_.ids.size(), Point4{});
    moved_.assign(movers_.ids.size(), 0);
    mobility_.assign(movers_.ids.size(), 1);
    for (std::uint32_t i = 0; i < movers_.ids.size(); ++i) {
      // In space only, so that twins stay translates and the section moves by the move itself.
      const auto& nrm = movers_.normals[i];
      const double spatial = std::sqrt(nrm[0] * nrm[0] + nrm[1] * nrm[1] + nrm[2] * nrm[2]);
      const double length = std::sqrt(spatial * spatial + nrm[3] * nrm[3]);
      // A boundary nearly along time (near a cap) has little section to move.
      if (!(spatial > 0.2 * length)) continue;
      mover_of_[movers_.ids[i]] = i;
      for (int a = 0; a < 3; ++a) direction_[i][a] = nrm[a] / spatial;
    }
  }

  // Where each mover's μs come from and go to: its time does not change (the moves are in
  // space), so its hat weights are found once.
  void find_reach() {
    reach_.assign(movers_.ids.size(), Reach{});
    for (std::uint32_t i = 0; i < movers_.ids.size(); ++i) {
      const auto& side = movers_.sides[i];
      const auto hat = frames_.hat(mesh_.vertices[movers_.ids[i]][3]);
      for (int p = 0; p < 2; ++p) {
        reach_[i].first_row[p] = unknown(side[p], 0);
        for (int k = 0; k < 2; ++k)
          reach_[i].columns[p][k] = {unknown(side[p], hat[k].first), hat[k].second};
      }
    }
  }

  mesh::Mesh4& mesh_;
  const domain::SurfaceOracle& oracle_;
  const InterfaceVertices& movers_;
  const Frames frames_;
  const Labels labels_;
  const std::size_t nf_, n_;
  std::vector<double> target_;           // by unknown: the voxels' volume
  double cap_ = 0;                       // the largest move of a vertex
  std::vector<std::uint32_t> mover_of_;  // by glued vertex: its mover, or kNone
  std::vector<Point4> direction_;        // by mover: a move of 1 shifts its sections by 1
  std::vector<double> moved_;            // by mover: along its direction so far
  std::vector<double> mobility_;         // by mover: the share of its last move made
  // A mover's rows in J (a side's label at frame 0, or kNone; a frame adds its index) and its
  // columns: each side's label at the two frames of its hat, with their weights.
  struct Reach {
    std::array<std::uint32_t, 2> first_row{kNone, kNone};
    std::array<std::array<std::pair<std::uint32_t, double>, 2>, 2> columns{};
  };
  std::vector<Reach> reach_;                // by mover
  std::vector<std::vector<Share>> shares_;  // in facet order, by part
};

}  // namespace

FrameVolumeFit fit_frame_volumes(mesh::Mesh4& mesh, const domain::SurfaceOracle& oracle,
                                 const InterfaceVertices& movers, const RefineParams& params) {
  const auto begin = std::chrono::steady_clock::now();
  FrameVolumeFit report;
  const unsigned threads = working_threads(params);
  FrameFit fit(mesh, oracle, movers, threads);
  if (fit.unknowns() == 0 || movers.ids.empty()) return report;
  report.sections = fit.sections();
  std::vector<double> volume = fit.measure(threads);
  report.worst_before = report.worst_after = fit.worst(volume);
  const std::vector<Point4> start = mesh.vertices;
  // The shares are measured once: the moves are a fraction of a voxel.
  fit.measure_shares(threads);
  double error = fit.total_error(volume);
  while (report.rounds < kMaxRounds && std::abs(report.worst_after) > kEnough) {
    if (!fit.move(fit.solve_for(fit.jacobian(), volume), params)) break;
    ++report.rounds;
    volume = fit.measure(threads);
    report.worst_after = fit.worst(volume);
    // Where the guard or the mesh leaves a section out of reach (an end frame of an image closed
    // without its caps), another round costs as much and gives nothing.
    const double was = error;
    error = fit.total_error(volume);
    if (error > (1 - kLeastGain) * was) break;
  }
  for (std::uint32_t v = 0; v < mesh.vertices.size(); ++v) {
    double d2 = 0;
    for (int a = 0; a < 4; ++a)
      d2 += (mesh.vertices[v][a] - start[v][a]) * (mesh.vertices[v][a] - start[v][a]);
    report.largest_move = std::max(report.largest_move, std::sqrt(d2));
  }
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  return report;
}

}  // namespace mesh4d::refine
