// The topology certificate (mesh/topology_certificate.h) on meshes known by construction, and on
// refined phantoms against an independent brute-force verifier written here with other means
// (sets of ids, searches over every facet, breadth-first walks, each vertex's link checked as a
// circle inside the link); a pentatope relabeled by hand must show up in both.
#include "mesh/topology_certificate.h"

#include <gtest/gtest.h>

#include <map>
#include <queue>
#include <set>

#include "domain/phantoms.h"
#include "domain/surface_oracle.h"
#include "mesh/test_meshes.h"
#include "refine/refiner.h"

namespace mesh4d::mesh {
namespace {

using Ids = std::set<std::uint32_t>;

// Pentatopes from vertex ids, with made-up coordinates (the topology alone matters here, but the
// volume needs them: vertex i at (i, i², i³, i⁴) keeps every pentatope full-dimensional).
Mesh4 from_pentatopes(const std::vector<std::array<std::uint32_t, 5>>& pentatopes,
                      const std::vector<Label>& labels) {
  Mesh4 m;
  std::uint32_t top = 0;
  for (const auto& p : pentatopes)
    for (auto v : p) top = std::max(top, v + 1);
  for (std::uint32_t i = 0; i < top; ++i) {
    const double x = 1 + 0.1 * i;
    m.vertices.push_back({x, x * x, x * x * x, x * x * x * x});
    m.vertex_kinds.push_back(VertexKind::feature);
  }
  m.pentatopes = pentatopes;
  m.labels = labels;
  add_hull(m);
  add_interfaces(m);
  return m;
}

// The refiner's boundary list, made again from the pentatopes' labels (after a planted change).
void relist_boundary(Mesh4& m) {
  m.boundary.clear();
  add_hull(m);
  add_interfaces(m);
}

// ---- The brute-force verifier ----------------------------------------------------------------

struct Brute {
  std::map<Label, std::size_t> components, non_manifold_vertices, non_manifold_edges,
      non_manifold_triangles;
};

// Whether a set of triangles is a 2-sphere: connected through shared edges, each edge in two,
// each vertex's triangles forming one cycle, and V − E + F = 2.
bool brute_sphere(const std::vector<Ids>& triangles) {
  std::map<Ids, std::vector<std::size_t>> by_edge;
  std::set<std::uint32_t> vertices;
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (auto a : triangles[t]) {
      vertices.insert(a);
      Ids e = triangles[t];
      e.erase(a);
      by_edge[e].push_back(t);
    }
  for (const auto& [e, ts] : by_edge)
    if (ts.size() != 2) return false;
  std::vector<bool> seen(triangles.size(), false);
  std::queue<std::size_t> frontier;
  frontier.push(0);
  seen[0] = true;
  while (!frontier.empty()) {
    const std::size_t t = frontier.front();
    frontier.pop();
    for (const auto& [e, ts] : by_edge)
      if (std::includes(triangles[t].begin(), triangles[t].end(), e.begin(), e.end()))
        for (std::size_t u : ts)
          if (!seen[u]) seen[u] = true, frontier.push(u);
  }
  if (std::find(seen.begin(), seen.end(), false) != seen.end()) return false;
  for (auto v : vertices) {  // the triangles at v: their opposite edges form one cycle
    std::vector<Ids> ring;
    for (const auto& t : triangles)
      if (t.count(v)) {
        Ids e = t;
        e.erase(v);
        ring.push_back(e);
      }
    std::map<std::uint32_t, int> degree;
    for (const auto& e : ring)
      for (auto a : e) ++degree[a];
    for (const auto& [a, d] : degree)
      if (d != 2) return false;
    if (degree.size() != ring.size()) return false;  // one cycle through all: as many edges
  }
  return static_cast<long>(vertices.size()) - static_cast<long>(by_edge.size()) +
             static_cast<long>(triangles.size()) ==
         2;
}

Brute brute_force(const Mesh4& m) {
  Brute out;
  const std::size_t n = m.pentatopes.size();
  std::vector<Ids> cells(n);
  for (std::size_t p = 0; p < n; ++p)
    cells[p] = Ids(m.pentatopes[p].begin(), m.pentatopes[p].end());
  std::map<Ids, std::vector<std::size_t>> facet_cells;
  for (std::size_t p = 0; p < n; ++p)
    for (auto v : cells[p]) {
      Ids f = cells[p];
      f.erase(v);
      facet_cells[f].push_back(p);
    }
  // Pieces, by breadth-first walks across facets shared within a label.
  std::vector<int> piece(n, -1);
  for (std::size_t s = 0; s < n; ++s) {
    if (piece[s] >= 0) continue;
    ++out.components[m.labels[s]];
    std::queue<std::size_t> frontier;
    frontier.push(s);
    piece[s] = static_cast<int>(s);
    while (!frontier.empty()) {
      const std::size_t p = frontier.front();
      frontier.pop();
      for (auto v : cells[p]) {
        Ids f = cells[p];
        f.erase(v);
        for (std::size_t q : facet_cells[f])
          if (piece[q] < 0 && m.labels[q] == m.labels[p])
            piece[q] = static_cast<int>(s), frontier.push(q);
      }
    }
  }
  // Each label's boundary facets, then every simplex of them with its link.
  std::map<Label, std::vector<Ids>> boundary;
  for (const auto& [f, ps] : facet_cells)
    for (std::size_t p : ps) {
      bool shared = false;
      for (std::size_t q : ps) shared |= q != p && m.labels[q] == m.labels[p];
      if (!shared) boundary[m.labels[p]].push_back(f);
    }
  for (const auto& [label, facets] : boundary) {
    // The facets at each vertex (the searches below go through these, not the whole list).
    std::map<std::uint32_t, std::vector<Ids>> at_vertex;
    for (const auto& f : facets)
      for (auto a : f) at_vertex[a].push_back(f);
    std::set<Ids> vertices, edges, triangles;
    for (const auto& f : facets)
      for (auto a : f) {
        vertices.insert({a});
        for (auto b : f)
          if (a < b) edges.insert({a, b});
        Ids t = f;
        t.erase(a);
        triangles.insert(t);
      }
    for (const auto& t : triangles) {
      std::size_t count = 0;
      for (const auto& f : at_vertex[*t.begin()])
        count += std::includes(f.begin(), f.end(), t.begin(), t.end());
      out.non_manifold_triangles[label] += count != 2;
    }
    for (const auto& e : edges) {  // the link: the facets' other two vertices, one cycle
      std::vector<Ids> link;
      for (const auto& f : at_vertex[*e.begin()])
        if (std::includes(f.begin(), f.end(), e.begin(), e.end())) {
          Ids rest = f;
          for (auto a : e) rest.erase(a);
          link.push_back(rest);
        }
      std::map<std::uint32_t, std::vector<std::uint32_t>> next;
      for (const auto& r : link) {
        next[*r.begin()].push_back(*r.rbegin());
        next[*r.rbegin()].push_back(*r.begin());
      }
      bool circle = true;
      for (const auto& [a, ns] : next) circle &= ns.size() == 2;
      if (circle) {  // walk it: one cycle through every vertex
        std::uint32_t prev = next.begin()->first, at = next.begin()->second[0];
        std::size_t steps = 1;
        while (at != next.begin()->first && steps <= next.size()) {
          const std::uint32_t go = next[at][0] == prev ? next[at][1] : next[at][0];
          prev = at, at = go, ++steps;
        }
        circle = steps == next.size();
      }
      out.non_manifold_edges[label] += !circle;
    }
    for (const auto& v : vertices) {
      std::vector<Ids> link;
      for (const auto& f : at_vertex[*v.begin()]) {
        Ids rest = f;
        rest.erase(*v.begin());
        link.push_back(rest);
      }
      out.non_manifold_vertices[label] += !brute_sphere(link);
    }
  }
  return out;
}

std::size_t at(const std::map<Label, std::size_t>& m, Label l) {
  const auto it = m.find(l);
  return it == m.end() ? 0 : it->second;
}

void expect_agree(const Mesh4& m, const std::string& what) {
  const TopologyCertificate c = certify_topology(m);
  const Brute b = brute_force(m);
  for (const LabelTopology& l : c.labels) {
    EXPECT_EQ(l.components, at(b.components, l.label)) << what << ", label " << l.label;
    EXPECT_EQ(l.non_manifold_vertices, at(b.non_manifold_vertices, l.label))
        << what << ", label " << l.label;
    EXPECT_EQ(l.non_manifold_edges, at(b.non_manifold_edges, l.label))
        << what << ", label " << l.label;
    EXPECT_EQ(l.non_manifold_triangles, at(b.non_manifold_triangles, l.label))
        << what << ", label " << l.label;
  }
}

const LabelTopology& label(const TopologyCertificate& c, Label l) {
  for (const auto& x : c.labels)
    if (x.label == l) return x;
  throw std::out_of_range("no such label");
}

// ---- Meshes known by construction ------------------------------------------------------------

TEST(TopologyCertificate, OnePentatopeAndTwoSharingAFacetAreOneManifoldPiece) {
  for (const Mesh4& m :
       {from_pentatopes({{0, 1, 2, 3, 4}}, {1}),
        from_pentatopes({{0, 1, 2, 3, 4}, {1, 2, 3, 4, 5}}, {1, 1}), kuhn_box(1, 2, 3)}) {
    Mesh4 mesh = m;
    if (mesh.boundary.empty()) add_hull(mesh);
    const TopologyCertificate c = certify_topology(mesh);
    ASSERT_EQ(c.labels.size(), 1u);
    EXPECT_EQ(c.labels[0].components, 1u);
    EXPECT_EQ(c.labels[0].touching_components, 0u);
    EXPECT_TRUE(c.manifold());
    expect_agree(mesh, "known");
  }
  Mesh4 box = kuhn_box(1, 2, 3);
  add_hull(box);
  EXPECT_NEAR(certify_topology(box).labels[0].volume, 6.0, 1e-12);
}

TEST(TopologyCertificate, PiecesThatMeetAtAVertexAnEdgeOrATriangleAreNamed) {
  struct Case {
    const char* contact;
    std::array<std::uint32_t, 5> second;
    std::size_t vertices, edges, triangles;
  };
  for (const Case& k :
       {Case{"vertex", {4, 5, 6, 7, 8}, 1, 0, 0}, Case{"edge", {3, 4, 5, 6, 7}, 2, 1, 0},
        Case{"triangle", {2, 3, 4, 5, 6}, 3, 3, 1}}) {
    const Mesh4 m = from_pentatopes({{0, 1, 2, 3, 4}, k.second}, {1, 1});
    const TopologyCertificate c = certify_topology(m);
    const LabelTopology& l = label(c, 1);
    EXPECT_EQ(l.components, 2u) << k.contact;
    EXPECT_EQ(l.touching_components, 2u) << k.contact;
    EXPECT_EQ(l.non_manifold_vertices, k.vertices) << k.contact;
    EXPECT_EQ(l.non_manifold_edges, k.edges) << k.contact;
    EXPECT_EQ(l.non_manifold_triangles, k.triangles) << k.contact;
    EXPECT_FALSE(c.manifold());
    expect_agree(m, k.contact);
    // Two labels meeting there are each one manifold piece.
    const TopologyCertificate two =
        certify_topology(from_pentatopes({{0, 1, 2, 3, 4}, k.second}, {1, 2}));
    EXPECT_TRUE(two.manifold()) << k.contact;
    EXPECT_EQ(label(two, 2).touching_components, 0u);
  }
}

TEST(TopologyCertificate, AMissingOrExtraBoundaryListEntryIsAMismatch) {
  Mesh4 m = from_pentatopes({{0, 1, 2, 3, 4}, {1, 2, 3, 4, 5}}, {1, 2});
  ASSERT_TRUE(certify_topology(m).manifold());
  m.boundary.pop_back();
  EXPECT_EQ(label(certify_topology(m), m.labels[0]).boundary_list_mismatches +
                label(certify_topology(m), m.labels[1]).boundary_list_mismatches,
            1u);
  EXPECT_FALSE(certify_topology(m).manifold());
}

// ---- Refined phantoms, and a planted defect ---------------------------------------------------

refine::RefineResult refined(const domain::LabelImage4& image, double delta) {
  domain::LabelImage4 closed = image;
  domain::validate_and_close(closed);
  const domain::SurfaceOracle oracle(closed);
  refine::RefineParams params;
  params.delta = delta;
  return refine::refine(oracle, params);
}

TEST(TopologyCertificate, AgreesWithTheBruteForceOnRefinedPhantoms) {
  const Mesh4 sphere =
      refined(domain::hypersphere_phantom({16, 16, 16, 16}, {1, 1, 1, 1}, 5), 2).mesh;
  const TopologyCertificate c = certify_topology(sphere);
  ASSERT_EQ(c.labels.size(), 1u);
  EXPECT_EQ(c.labels[0].components, 1u);
  EXPECT_TRUE(c.manifold());
  expect_agree(sphere, "hypersphere");
  const Mesh4 ventricle =
      refined(domain::beating_ventricle_phantom({40, 40, 16, 6}, {4.4, 4.4, 16, 3}), 8).mesh;
  for (const LabelTopology& l : certify_topology(ventricle).labels)
    std::printf(
        "ventricle label %u: %zu pentatopes, %zu pieces (%zu touching another), non-manifold "
        "vertices %zu, edges %zu, triangles %zu\n",
        unsigned{l.label}, l.pentatopes, l.components, l.touching_components,
        l.non_manifold_vertices, l.non_manifold_edges, l.non_manifold_triangles);
  expect_agree(ventricle, "ventricle");
}

TEST(TopologyCertificate, APentatopeRelabeledByHandIsFound) {
  Mesh4 m = refined(domain::beating_ventricle_phantom({40, 40, 16, 6}, {4.4, 4.4, 16, 3}), 8).mesh;
  const TopologyCertificate before = certify_topology(m);
  // A pool pentatope (label 1) that touches the wall (label 2) at a vertex but shares no facet
  // with it: as wall it is a piece of its own that meets the wall at a vertex or an edge.
  const auto owners = facet_owners(m);
  std::map<std::uint32_t, std::set<Label>> labels_at;
  for (std::size_t p = 0; p < m.pentatopes.size(); ++p)
    for (auto v : m.pentatopes[p]) labels_at[v].insert(m.labels[p]);
  std::size_t planted = m.pentatopes.size();
  for (std::size_t p = 0; p < m.pentatopes.size() && planted == m.pentatopes.size(); ++p) {
    if (m.labels[p] != 1) continue;
    bool touches = false, shares = false;
    for (auto v : m.pentatopes[p]) touches |= labels_at[v].count(2) > 0;
    for (int skip = 0; skip < 5; ++skip) {
      std::array<std::uint32_t, 4> f;
      for (int k = 0, j = 0; k < 5; ++k)
        if (k != skip) f[j++] = m.pentatopes[p][k];
      std::sort(f.begin(), f.end());
      for (auto q : owners.at(f)) shares |= q != p && m.labels[q] == 2;
    }
    if (touches && !shares) planted = p;
  }
  ASSERT_LT(planted, m.pentatopes.size()) << "no pool pentatope touches the wall at a vertex only";
  m.labels[planted] = 2;
  EXPECT_FALSE(certify_topology(m).manifold()) << "the boundary list no longer matches";
  relist_boundary(m);
  const TopologyCertificate after = certify_topology(m);
  EXPECT_EQ(label(after, 2).components, label(before, 2).components + 1);
  EXPECT_GT(label(after, 2).touching_components, label(before, 2).touching_components);
  EXPECT_GT(label(after, 2).non_manifold_vertices, label(before, 2).non_manifold_vertices);
  EXPECT_FALSE(after.manifold());
  expect_agree(m, "planted");
}

}  // namespace
}  // namespace mesh4d::mesh

namespace mesh4d::mesh {
namespace {

// An n⁴ grid of unit hypercubes, each as its 24 Kuhn pentatopes, labeled by blocks that meet
// at vertices, edges and faces: large enough for the certificate to split its work.
Mesh4 labeled_kuhn_grid(int n) {
  Mesh4 m;
  const auto id = [&](int x, int y, int z, int t) {
    return static_cast<std::uint32_t>(((t * (n + 1) + z) * (n + 1) + y) * (n + 1) + x);
  };
  for (int t = 0; t <= n; ++t)
    for (int z = 0; z <= n; ++z)
      for (int y = 0; y <= n; ++y)
        for (int x = 0; x <= n; ++x) {
          m.vertices.push_back({double(x), double(y), double(z), double(t)});
          m.vertex_kinds.push_back(VertexKind::free);
        }
  for (int t = 0; t < n; ++t)
    for (int z = 0; z < n; ++z)
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const Label l = static_cast<Label>(1 + (x / 3 + 2 * (y / 2) + z / 3 + t / 4) % 3);
          std::array<int, 4> axes{0, 1, 2, 3};
          do {
            std::array<int, 4> c{x, y, z, t};
            std::array<std::uint32_t, 5> p{};
            p[0] = id(c[0], c[1], c[2], c[3]);
            for (int k = 0; k < 4; ++k) {
              ++c[axes[k]];
              p[k + 1] = id(c[0], c[1], c[2], c[3]);
            }
            m.pentatopes.push_back(p);
            m.labels.push_back(l);
          } while (std::next_permutation(axes.begin(), axes.end()));
        }
  add_hull(m);
  add_interfaces(m);
  return m;
}

TEST(TopologyCertificate, ThreadsGiveTheSameCertificateOnALargeMesh) {
  const Mesh4 m = labeled_kuhn_grid(9);  // 157,464 pentatopes: split four ways
  const TopologyCertificate one = certify_topology(m, 1);
  ASSERT_EQ(one.labels.size(), 3u);
  std::size_t pieces = 0;
  for (const LabelTopology& l : one.labels) pieces += l.components;
  EXPECT_GT(pieces, 3u);
  for (const unsigned threads : {2u, 3u, 4u}) {
    const TopologyCertificate many = certify_topology(m, threads);
    ASSERT_EQ(many.labels.size(), one.labels.size());
    for (std::size_t i = 0; i < one.labels.size(); ++i) {
      const LabelTopology &a = one.labels[i], &b = many.labels[i];
      SCOPED_TRACE(std::to_string(threads) + " threads, label " + std::to_string(a.label));
      EXPECT_EQ(b.label, a.label);
      EXPECT_EQ(b.pentatopes, a.pentatopes);
      EXPECT_EQ(b.components, a.components);
      EXPECT_EQ(b.touching_components, a.touching_components);
      EXPECT_EQ(b.boundary_facets, a.boundary_facets);
      EXPECT_EQ(b.non_manifold_triangles, a.non_manifold_triangles);
      EXPECT_EQ(b.non_manifold_edges, a.non_manifold_edges);
      EXPECT_EQ(b.non_manifold_vertices, a.non_manifold_vertices);
      EXPECT_EQ(b.boundary_list_mismatches, a.boundary_list_mismatches);
      EXPECT_EQ(b.volume, a.volume);
    }
  }
}

}  // namespace
}  // namespace mesh4d::mesh
