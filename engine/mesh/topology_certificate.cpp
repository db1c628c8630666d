#include "mesh/topology_certificate.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <tuple>

#include "mesh/link_topology.h"
#include "mesh/periodic_mesh.h"
#include "support/concurrent_union_find.h"
#include "support/parallel_parts.h"
#include "support/parallel_sort.h"

namespace mesh4d::mesh {
namespace {

using Id = std::uint32_t;
using support::ConcurrentUnionFind;

template <std::size_t N>
std::array<Id, N> sorted(std::array<Id, N> a) {
  std::sort(a.begin(), a.end());
  return a;
}

// A region's boundary facet: its label, its vertices (sorted).
struct BoundaryFacet {
  Label label;
  std::array<Id, 4> v;
  bool operator<(const BoundaryFacet& o) const {
    return std::tie(label, v) < std::tie(o.label, o.v);
  }
  bool operator==(const BoundaryFacet& o) const { return label == o.label && v == o.v; }
};

double four_volume(const Mesh4& mesh, const std::array<Id, 5>& p) {
  double m[4][4];
  const Point4& o = mesh.vertices[p[0]];
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = mesh.vertices[p[r + 1]][c] - o[c];
  // The determinant by elimination with partial pivoting.
  double det = 1;
  for (int c = 0; c < 4; ++c) {
    int pivot = c;
    for (int r = c + 1; r < 4; ++r)
      if (std::abs(m[r][c]) > std::abs(m[pivot][c])) pivot = r;
    if (m[pivot][c] == 0) return 0;
    if (pivot != c) {
      std::swap(m[pivot], m[c]);
      det = -det;
    }
    det *= m[c][c];
    for (int r = c + 1; r < 4; ++r) {
      const double f = m[r][c] / m[c][c];
      for (int k = c; k < 4; ++k) m[r][k] -= f * m[c][k];
    }
  }
  return std::abs(det) / 24;
}

}  // namespace

bool TopologyCertificate::manifold() const {
  for (const LabelTopology& l : labels)
    if (l.non_manifold_triangles || l.non_manifold_edges || l.non_manifold_vertices ||
        l.boundary_list_mismatches)
      return false;
  return true;
}

TopologyCertificate certify_topology(const Mesh4& unglued, unsigned threads) {
  // In periodic time the combinatorics are the glued cycle's; the volumes, the positions'.
  const Mesh4 glued_cycle = unglued.periodic() ? glued(unglued) : Mesh4{};
  const Mesh4& mesh = unglued.periodic() ? glued_cycle : unglued;
  const std::size_t n = mesh.pentatopes.size();
  std::map<Label, LabelTopology> by_label;
  for (std::size_t p = 0; p < n; ++p) {
    LabelTopology& l = by_label[mesh.labels[p]];
    l.label = mesh.labels[p];
    ++l.pentatopes;
    l.volume += four_volume(unglued, unglued.pentatopes[p]);
  }

  // Facets: pentatopes of one label that share one are one piece; a facet that no other
  // pentatope of the label shares bounds the label's region.
  std::vector<std::pair<std::array<Id, 4>, Id>> facets(5 * n);
  const unsigned parts = support::parts_for(n, support::kMinSortShare, threads);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(n, part, parts);
    for (std::size_t p = begin; p < end; ++p)
      for (int skip = 0; skip < 5; ++skip) {
        std::array<Id, 4> f;
        for (int k = 0, m = 0; k < 5; ++k)
          if (k != skip) f[m++] = mesh.pentatopes[p][k];
        facets[5 * p + static_cast<std::size_t>(skip)] = {sorted(f), static_cast<Id>(p)};
      }
  });
  support::parallel_sort(facets, threads);
  // The runs of equal facets split among the threads (a share starts at the first run that
  // begins in it); the pieces, counted below, do not depend on which element roots them, and
  // the boundary facets come in the sorted order whatever the threads.
  ConcurrentUnionFind pieces(n);
  const auto run_start = [&](std::size_t i) {
    while (i > 0 && i < facets.size() && facets[i].first == facets[i - 1].first) ++i;
    return i;
  };
  std::vector<std::vector<BoundaryFacet>> boundary_parts(parts);
  support::run_parts(parts, [&](unsigned part) {
    const std::size_t begin = run_start(support::part_range(facets.size(), part, parts).first);
    const std::size_t end = run_start(support::part_range(facets.size(), part, parts).second);
    for (std::size_t i = begin; i < end;) {
      std::size_t j = i;
      while (j < facets.size() && facets[j].first == facets[i].first) ++j;
      for (std::size_t a = i; a < j; ++a) {
        bool shared = false;
        for (std::size_t b = i; b < j; ++b)
          if (b != a && mesh.labels[facets[b].second] == mesh.labels[facets[a].second]) {
            shared = true;
            pieces.join(facets[a].second, facets[b].second);
          }
        if (!shared)
          boundary_parts[part].push_back({mesh.labels[facets[a].second], facets[a].first});
      }
      i = j;
    }
  });
  std::vector<BoundaryFacet> boundary;
  for (const auto& b : boundary_parts) boundary.insert(boundary.end(), b.begin(), b.end());
  boundary_parts = {};

  // Pieces, and those that meet another piece of their label at a vertex (an edge or a
  // triangle contact has its vertices too).
  std::map<Label, std::vector<std::size_t>> roots;
  for (std::size_t p = 0; p < n; ++p)
    if (pieces.find(p) == p) roots[mesh.labels[p]].push_back(p);
  // The pentatopes at each vertex, by a counting sort (first[v] .. first[v + 1] in star).
  std::vector<std::size_t> first(mesh.vertices.size() + 1, 0);
  for (const auto& cell : mesh.pentatopes)
    for (Id v : cell) ++first[v + 1];
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) first[v + 1] += first[v];
  std::vector<Id> star(5 * n);
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t p = 0; p < n; ++p)
      for (Id v : mesh.pentatopes[p]) star[next[v]++] = static_cast<Id>(p);
  }
  std::vector<bool> touching(n, false);
  std::vector<std::pair<Label, std::size_t>> around;  // (label, piece) at one vertex
  for (std::size_t v = 0; v < mesh.vertices.size(); ++v) {
    around.clear();
    for (std::size_t k = first[v]; k < first[v + 1]; ++k)
      around.push_back({mesh.labels[star[k]], pieces.find(star[k])});
    std::sort(around.begin(), around.end());
    around.erase(std::unique(around.begin(), around.end()), around.end());
    for (std::size_t a = 0; a + 1 < around.size(); ++a)
      if (around[a].first == around[a + 1].first)
        touching[around[a].second] = touching[around[a + 1].second] = true;
  }
  for (auto& [label, list] : roots) {
    by_label[label].components = list.size();
    for (std::size_t r : list) by_label[label].touching_components += touching[r];
  }

  // The links of the boundary's vertices first. Where a vertex's link is a 2-sphere (a closed
  // surface), the links of the edges and triangles through it are links within that surface:
  // a circle and two points. So only edges and triangles whose every vertex failed need looking
  // at (on the patients a few thousand of a million).
  std::vector<std::tuple<Label, Id, std::array<Id, 3>>> vertex_links;
  vertex_links.reserve(4 * boundary.size());
  for (const BoundaryFacet& f : boundary) {
    ++by_label[f.label].boundary_facets;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Id, 3> t;
      for (int k = 0, m = 0; k < 4; ++k)
        if (k != skip) t[m++] = f.v[k];
      vertex_links.emplace_back(f.label, f.v[skip], t);
    }
  }
  support::parallel_sort(vertex_links, threads);
  // Each (label, vertex)'s run of link triangles, then the runs' links checked on the threads.
  std::vector<std::size_t> runs;
  for (std::size_t i = 0; i < vertex_links.size(); ++i)
    if (i == 0 || std::get<0>(vertex_links[i]) != std::get<0>(vertex_links[i - 1]) ||
        std::get<1>(vertex_links[i]) != std::get<1>(vertex_links[i - 1]))
      runs.push_back(i);
  runs.push_back(vertex_links.size());
  std::vector<std::uint8_t> sphere_link(runs.size() - 1, 1);
  const unsigned link_parts = support::parts_for(runs.size(), 1024, threads);
  support::run_parts(link_parts, [&](unsigned part) {
    std::vector<std::array<Id, 3>> sphere;
    const auto [begin, end] = support::part_range(runs.size() - 1, part, link_parts);
    for (std::size_t r = begin; r < end; ++r) {
      sphere.clear();
      for (std::size_t k = runs[r]; k < runs[r + 1]; ++k)
        sphere.push_back(std::get<2>(vertex_links[k]));
      sphere_link[r] = link_is_sphere(sphere);
    }
  });
  std::vector<std::pair<Label, Id>> failed;  // (label, vertex), sorted
  for (std::size_t r = 0; r + 1 < runs.size(); ++r)
    if (!sphere_link[r]) {
      const Label label = std::get<0>(vertex_links[runs[r]]);
      ++by_label[label].non_manifold_vertices;
      failed.push_back({label, std::get<1>(vertex_links[runs[r]])});
    }
  vertex_links = {};
  const auto fails = [&](Label label, Id v) {
    return std::binary_search(failed.begin(), failed.end(), std::pair<Label, Id>{label, v});
  };

  std::vector<std::array<Id, 4>> triangles;  // (label, triangle), once per facet
  std::vector<std::tuple<Label, std::array<Id, 2>, std::array<Id, 2>>> edge_links;
  for (const BoundaryFacet& f : boundary) {
    std::array<bool, 4> bad;
    int bad_count = 0;
    for (int k = 0; k < 4; ++k) bad_count += bad[k] = fails(f.label, f.v[k]);
    if (bad_count < 2) continue;
    for (int skip = 0; skip < 4; ++skip) {
      std::array<Id, 4> t{f.label, 0, 0, 0};
      bool all_bad = true;
      for (int k = 0, m = 1; k < 4; ++k)
        if (k != skip) t[m++] = f.v[k], all_bad &= bad[k];
      if (all_bad) triangles.push_back(t);
    }
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        if (!bad[a] || !bad[b]) continue;
        std::array<Id, 2> rest;
        for (int k = 0, m = 0; k < 4; ++k)
          if (k != a && k != b) rest[m++] = f.v[k];
        edge_links.emplace_back(f.label, std::array<Id, 2>{f.v[a], f.v[b]}, rest);
      }
  }
  support::parallel_sort(triangles, threads);
  for (std::size_t i = 0; i < triangles.size();) {
    std::size_t j = i;
    while (j < triangles.size() && triangles[j] == triangles[i]) ++j;
    if (j - i != 2) ++by_label[static_cast<Label>(triangles[i][0])].non_manifold_triangles;
    i = j;
  }
  support::parallel_sort(edge_links, threads);
  std::vector<std::array<Id, 2>> circle;
  for (std::size_t i = 0; i < edge_links.size();) {
    std::size_t j = i;
    circle.clear();
    for (; j < edge_links.size() && std::get<0>(edge_links[j]) == std::get<0>(edge_links[i]) &&
           std::get<1>(edge_links[j]) == std::get<1>(edge_links[i]);
         ++j)
      circle.push_back(std::get<2>(edge_links[j]));
    if (!link_is_circle(circle)) ++by_label[std::get<0>(edge_links[i])].non_manifold_edges;
    i = j;
  }

  // The mesh's own boundary list against the computed one.
  std::vector<BoundaryFacet> listed;
  listed.reserve(mesh.boundary.size());
  for (const BoundaryTetrahedron& b : mesh.boundary)
    listed.push_back({b.inner, sorted(b.vertices)});
  support::parallel_sort(listed, threads);
  support::parallel_sort(boundary, threads);
  std::vector<BoundaryFacet> differ;
  std::set_symmetric_difference(boundary.begin(), boundary.end(), listed.begin(), listed.end(),
                                std::back_inserter(differ));
  for (const BoundaryFacet& f : differ) ++by_label[f.label].boundary_list_mismatches;

  TopologyCertificate certificate;
  for (auto& [label, l] : by_label) {
    l.label = label;
    certificate.labels.push_back(l);
  }
  return certificate;
}

}  // namespace mesh4d::mesh
