// Simple relabeling: asked to move every pentatope to a neighbor's label, it moves many and
// changes no region's topology, as an outside verifier counts it (pieces, pieces touching at
// lower faces, the links of boundary vertices, edges and triangles), and the boundary list it
// makes again is the true one. Three labels meet the outside on the moving junction, and two
// labels and their meeting with the outside on the ventricle, in open and periodic time.
#include "refine/simple_relabeling.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdio>
#include <map>
#include <vector>

#include "domain/label_image.h"
#include "domain/phantoms.h"
#include "mesh/periodic_mesh.h"
#include "mesh/topology_certificate.h"
#include "refine/periodic_time.h"
#include "refine/refine_checks.h"
#include "refine/refiner.h"

namespace mesh4d::refine {
namespace {

// For each pentatope, the labels across its facets (0: the outside), in the glued mesh.
std::vector<std::array<mesh::Label, 5>> labels_across(const mesh::Mesh4& mesh) {
  const std::vector<std::uint32_t> glued = mesh::glued_vertex_ids(mesh);
  std::map<std::array<std::uint32_t, 4>, std::vector<std::pair<std::uint32_t, int>>> facets;
  for (std::uint32_t p = 0; p < mesh.pentatopes.size(); ++p)
    for (int i = 0; i < 5; ++i) {
      std::array<std::uint32_t, 4> key;
      for (int k = 0, m = 0; k < 5; ++k)
        if (k != i) key[m++] = glued[mesh.pentatopes[p][k]];
      std::sort(key.begin(), key.end());
      facets[key].push_back({p, i});
    }
  std::vector<std::array<mesh::Label, 5>> across(mesh.pentatopes.size(), {0, 0, 0, 0, 0});
  for (const auto& [key, sides] : facets)
    if (sides.size() == 2) {
      across[sides[0].first][sides[0].second] = mesh.labels[sides[1].first];
      across[sides[1].first][sides[1].second] = mesh.labels[sides[0].first];
    }
  return across;
}

void expect_same_topology(const mesh::TopologyCertificate& before,
                          const mesh::TopologyCertificate& after) {
  ASSERT_EQ(before.labels.size(), after.labels.size());
  for (std::size_t i = 0; i < before.labels.size(); ++i) {
    const mesh::LabelTopology &b = before.labels[i], &a = after.labels[i];
    SCOPED_TRACE(testing::Message() << "label " << b.label);
    EXPECT_EQ(a.components, b.components);
    EXPECT_EQ(a.touching_components, b.touching_components);
    EXPECT_EQ(a.non_manifold_vertices, b.non_manifold_vertices);
    EXPECT_EQ(a.non_manifold_edges, b.non_manifold_edges);
    EXPECT_EQ(a.non_manifold_triangles, b.non_manifold_triangles);
    EXPECT_EQ(a.boundary_list_mismatches, 0u) << "the boundary list made again is the true one";
  }
}

// Asks each pentatope to take the label across its first facet that has another label, twice
// over (the second round asks the moved ones again), and checks the topology after each.
void relabel_everything(mesh::Mesh4 mesh) {
  const mesh::TopologyCertificate before = mesh::certify_topology(mesh);
  ASSERT_TRUE(before.manifold());
  for (int round = 0; round < 2; ++round) {
    const auto across = labels_across(mesh);
    const std::vector<mesh::Label> was = mesh.labels;
    const std::size_t moved = relabel_simple(mesh, [&](std::uint32_t p) -> mesh::Label {
      for (mesh::Label l : across[p])
        if (l != 0 && l != was[p]) return l;
      return 0;
    });
    std::size_t changed = 0;
    for (std::size_t p = 0; p < was.size(); ++p) changed += mesh.labels[p] != was[p];
    std::printf("round %d: %zu of %zu pentatopes moved\n", round, moved, mesh.pentatopes.size());
    EXPECT_EQ(moved, changed);
    EXPECT_GT(moved, mesh.pentatopes.size() / 100) << "round " << round;
    expect_same_topology(before, mesh::certify_topology(mesh));
  }
}

TEST(SimpleRelabeling, ThreeLabelsAndTheOutsideKeepTheirTopology) {
  domain::LabelImage4 image = domain::moving_junction_phantom();
  domain::validate_and_close(image);
  const domain::SurfaceOracle oracle(image);
  RefineParams params;
  params.delta = 2.5;
  relabel_everything(refine(oracle, params).mesh);
}

TEST(SimpleRelabeling, PeriodicTimeKeepsItsTopologyAcrossTheSeam) {
  const domain::LabelImage4 image = small_ventricle();
  RefineParams params;
  params.delta = 8;
  std::vector<std::string> warnings;
  const RefineResult r = refine_periodic(image, params, nullptr, &warnings);
  ASSERT_TRUE(r.mesh.periodic());
  relabel_everything(r.mesh);
}

}  // namespace
}  // namespace mesh4d::refine
