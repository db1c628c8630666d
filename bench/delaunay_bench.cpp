// delaunay_bench: mesh4d's 4D Delaunay insertion against CGAL's dD Delaunay_triangulation
// (Epick_d<Dimension_tag<4>>), on the same spatially sorted points in one run.
//
// Each measurement runs in a forked child so that its peak memory (VmHWM, reset before the run
// through /proc/self/clear_refs) belongs to that triangulation alone. Prints points/s,
// pentatopes, peak bytes per pentatope, the ratios, and mesh4d's exact-fallback rate.
//
// Then vertex removal (the refiner's R5) against CGAL's remove(), after the same insertions.
//
//   delaunay_bench [--max-n N] [--repeats R]     (defaults: 1000000, 3; N ≥ 10⁶ runs once)
#include <CGAL/Delaunay_triangulation.h>
#include <CGAL/Epick_d.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>
#include <string>
#include <vector>

#include "bench_util.h"
#include "delaunay/predicates.h"
#include "delaunay/spatial_sort.h"
#include "delaunay/triangulation.h"

namespace {

using mesh4d::Point4;
using Kernel = CGAL::Epick_d<CGAL::Dimension_tag<4>>;
using CgalDelaunay = CGAL::Delaunay_triangulation<Kernel>;

struct Measure {
  double seconds = 0;
  double cells = 0;       // finite pentatopes
  double peak_bytes = 0;  // peak resident memory above the start of the run
  // mesh4d: in-sphere calls per inserted point that went past the semi-static filter, that
  // needed double-double, and that needed multiprecision.
  double dynamic_per_point = 0, double_double_per_point = 0, exact_per_point = 0;
};

using mesh4d::bench::status_kb;

Measure run_mesh4d(const std::vector<Point4>& pts) {
  Measure m;
  const long base = status_kb("VmRSS:");
  auto& counters = mesh4d::delaunay::predicate_counters();
  counters = {};
  const auto t0 = std::chrono::steady_clock::now();
  mesh4d::delaunay::Triangulation t;
  mesh4d::delaunay::CellId hint = mesh4d::delaunay::kNoCell;
  for (const Point4& p : pts) hint = t.insert(p, mesh4d::delaunay::VertexKind::free, hint).cell;
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.peak_bytes = 1024.0 * (status_kb("VmHWM:") - base);
  m.cells = double(t.number_of_finite_cells());
  const double n = double(pts.size());
  m.dynamic_per_point = counters.insphere_dynamic / n;
  m.double_double_per_point = counters.insphere_double_double / n;
  m.exact_per_point = counters.insphere_exact / n;
  return m;
}

Measure run_cgal(const std::vector<Point4>& pts) {
  Measure m;
  std::vector<Kernel::Point_d> cp;
  for (const Point4& p : pts) cp.emplace_back(p[0], p[1], p[2], p[3]);
  const long base = status_kb("VmRSS:");
  const auto t0 = std::chrono::steady_clock::now();
  CgalDelaunay dt(4);
  // One point at a time with the previous cell as hint, the way refinement inserts (CGAL's
  // range insert would spatially sort again).
  CgalDelaunay::Full_cell_handle hint;
  for (const auto& p : cp) {
    auto v = dt.insert(p, hint);
    hint = v->full_cell();
  }
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.peak_bytes = 1024.0 * (status_kb("VmHWM:") - base);
  m.cells = double(dt.number_of_finite_full_cells());
  return m;
}

// Vertex removal (the refiner's R5): the triangulation of all points is built untimed, then the
// vertices of `doomed` (indices into pts, interior points) are removed one by one, timed.
// cells: finite pentatopes at the end, the same for both when both are right.
Measure remove_mesh4d(const std::vector<Point4>& pts, const std::vector<std::size_t>& doomed) {
  Measure m;
  mesh4d::delaunay::Triangulation t;
  std::vector<mesh4d::VertexId> ids;
  mesh4d::delaunay::CellId hint = mesh4d::delaunay::kNoCell;
  for (const Point4& p : pts) {
    const auto r = t.insert(p, mesh4d::delaunay::VertexKind::free, hint);
    ids.push_back(r.vertex);
    hint = r.cell;
  }
  std::vector<mesh4d::delaunay::CellId> created;
  std::size_t refused = 0;
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i : doomed) {
    created.clear();
    refused += !t.remove(ids[i], &created);
  }
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.cells = refused ? -1 : double(t.number_of_finite_cells());
  return m;
}

Measure remove_cgal(const std::vector<Point4>& pts, const std::vector<std::size_t>& doomed) {
  Measure m;
  CgalDelaunay dt(4);
  std::vector<CgalDelaunay::Vertex_handle> handles;
  CgalDelaunay::Full_cell_handle hint;
  for (const Point4& p : pts) {
    handles.push_back(dt.insert(Kernel::Point_d(p[0], p[1], p[2], p[3]), hint));
    hint = handles.back()->full_cell();
  }
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t i : doomed) dt.remove(handles[i]);
  m.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  m.cells = double(dt.number_of_finite_full_cells());
  return m;
}

// Runs f in a child process (fresh peak-memory counter) and returns its Measure.
template <class F>
Measure in_child(F f) {
  int fd[2];
  if (pipe(fd) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    std::ofstream("/proc/self/clear_refs") << "5";  // resets VmHWM to the current RSS
    const Measure m = f();
    if (write(fd[1], &m, sizeof m) != sizeof m) _exit(1);
    _exit(0);
  }
  close(fd[1]);
  Measure m;
  if (read(fd[0], &m, sizeof m) != sizeof m) std::fprintf(stderr, "child failed\n");
  close(fd[0]);
  waitpid(pid, nullptr, 0);
  return m;
}

Measure median(std::vector<Measure> v) {
  std::sort(v.begin(), v.end(),
            [](const Measure& a, const Measure& b) { return a.seconds < b.seconds; });
  return v[v.size() / 2];
}

void row(const char* input, const std::vector<Point4>& unsorted, int repeats) {
  std::vector<Point4> pts;
  for (std::size_t i : mesh4d::delaunay::spatial_order(unsorted)) pts.push_back(unsorted[i]);
  std::vector<Measure> ours, theirs;
  for (int r = 0; r < repeats; ++r) {
    ours.push_back(in_child([&] { return run_mesh4d(pts); }));
    theirs.push_back(in_child([&] { return run_cgal(pts); }));
  }
  const Measure a = median(ours), b = median(theirs);
  const double n = double(pts.size());
  std::printf(
      "| %s | %.0f | %d | %.0f | %.0f | %.2fx | %.0f | %.0f | %.1f | %.1f | %.2f / %.3f / %.4f |\n",
      input, n, repeats, n / a.seconds, n / b.seconds, b.seconds / a.seconds, a.cells, b.cells,
      a.peak_bytes / a.cells, b.peak_bytes / b.cells, a.dynamic_per_point,
      a.double_double_per_point, a.exact_per_point);
  std::fflush(stdout);
}

// Removes every tenth point (in spatial order) that lies at least `margin` inside the points'
// bounding box (so none is a hull vertex, which mesh4d refuses to remove).
void removal_row(const char* input, const std::vector<Point4>& unsorted, double margin,
                 int repeats) {
  std::vector<Point4> pts;
  for (std::size_t i : mesh4d::delaunay::spatial_order(unsorted)) pts.push_back(unsorted[i]);
  Point4 lo = pts[0], hi = pts[0];
  for (const Point4& p : pts)
    for (int k = 0; k < 4; ++k) lo[k] = std::min(lo[k], p[k]), hi[k] = std::max(hi[k], p[k]);
  std::vector<std::size_t> doomed;
  for (std::size_t i = 0; i < pts.size(); i += 10) {
    bool inside = true;
    for (int k = 0; k < 4; ++k)
      inside = inside && pts[i][k] > lo[k] + margin && pts[i][k] < hi[k] - margin;
    if (inside) doomed.push_back(i);
  }
  std::vector<Measure> ours, theirs;
  for (int r = 0; r < repeats; ++r) {
    ours.push_back(in_child([&] { return remove_mesh4d(pts, doomed); }));
    theirs.push_back(in_child([&] { return remove_cgal(pts, doomed); }));
  }
  const Measure a = median(ours), b = median(theirs);
  const double n = double(doomed.size());
  std::printf("| %s | %zu | %.0f | %d | %.0f | %.0f | %.2fx | %.0f | %.0f |\n", input, pts.size(),
              n, repeats, n / a.seconds, n / b.seconds, b.seconds / a.seconds, a.cells, b.cells);
  std::fflush(stdout);
}

std::vector<Point4> uniform(std::size_t n, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0, 100);
  std::vector<Point4> pts(n);
  for (auto& p : pts) p = {u(rng), u(rng), u(rng), u(rng)};
  return pts;
}

// A k⁴ grid with spacing 1, each coordinate moved by up to ±1e-12: nearly degenerate
// everywhere, the hard case for floating-point filters.
std::vector<Point4> jittered_grid(int k, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1e-12, 1e-12);
  std::vector<Point4> pts;
  for (int t = 0; t < k; ++t)
    for (int z = 0; z < k; ++z)
      for (int y = 0; y < k; ++y)
        for (int x = 0; x < k; ++x) pts.push_back({x + u(rng), y + u(rng), z + u(rng), t + u(rng)});
  return pts;
}

}  // namespace

int main(int argc, char** argv) {
  std::size_t max_n = 1'000'000;
  int repeats = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::strcmp(argv[i], "--max-n") == 0) max_n = std::stoul(argv[i + 1]);
    if (std::strcmp(argv[i], "--repeats") == 0) repeats = std::stoi(argv[i + 1]);
  }
  std::printf(
      "4D Delaunay insertion, spatially sorted, one point at a time with a hint; medians\n");
  std::printf(
      "| input | N | runs | mesh4d points/s | CGAL points/s | ratio | mesh4d pentatopes | CGAL "
      "pentatopes | mesh4d peak B/pentatope | CGAL peak B/pentatope | in-sphere past stage 1 / "
      "double-double / multiprecision, per point |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (std::size_t n : {std::size_t{10'000}, std::size_t{100'000}, std::size_t{1'000'000}}) {
    if (n > max_n) break;
    row("uniform", uniform(n, 42 + n), n >= 1'000'000 ? 1 : repeats);
  }
  const int k = max_n >= 1'000'000 ? 20 : 12;
  row(("jittered grid " + std::to_string(k) + "^4").c_str(), jittered_grid(k, 7), repeats);

  std::printf(
      "\n4D Delaunay vertex removal (every tenth interior point, one at a time); medians\n"
      "| input | N | removals | runs | mesh4d removals/s | CGAL removals/s | ratio | mesh4d "
      "pentatopes after | CGAL pentatopes after |\n|---|---|---|---|---|---|---|---|---|\n");
  removal_row("uniform", uniform(20'000, 5), 10, repeats);
  removal_row("jittered grid 10^4 (±1e-12)", jittered_grid(10, 9), 1.5, repeats);
  return 0;
}
