#include "mesh/mesh_io.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <set>

#include "mesh/mesh_check.h"
#include "mesh/mesh_stats.h"
#include "test_meshes.h"

namespace mesh4d::mesh {
namespace {

// Two pentatopes sharing a facet, with labels 1 and 2, and their outer boundary facets.
Mesh4 small_mesh() {
  Mesh4 m;
  m.vertices = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}, {1, 1, 1, 1}};
  m.vertex_kinds = {VertexKind::box,     VertexKind::feature, VertexKind::feature,
                    VertexKind::feature, VertexKind::free,    VertexKind::feature};
  m.pentatopes = {{0, 1, 2, 3, 4}, {1, 2, 3, 4, 5}};
  m.labels = {1, 2};
  m.boundary = {{{0, 1, 2, 3}, 0, 1, 0}, {{1, 2, 3, 4}, 0, 1, 2}, {{1, 2, 3, 5}, 1, 2, 0}};
  return m;
}

bool same(const Mesh4& a, const Mesh4& b) {
  if (a.boundary.size() != b.boundary.size()) return false;
  for (std::size_t i = 0; i < a.boundary.size(); ++i) {
    const auto &x = a.boundary[i], &y = b.boundary[i];
    if (x.vertices != y.vertices || x.pentatope != y.pentatope || x.inner != y.inner ||
        x.outer != y.outer)
      return false;
  }
  return a.vertices == b.vertices && a.vertex_kinds == b.vertex_kinds &&
         a.pentatopes == b.pentatopes && a.labels == b.labels;
}

TEST(M4d, RoundTripInMemoryAndThroughAFile) {
  const Mesh4 mesh = small_mesh();
  const auto bytes = encode_m4d(mesh);
  EXPECT_EQ(bytes.size() % 8, 0u);
  EXPECT_TRUE(same(decode_m4d(bytes.data(), bytes.size()), mesh));
  const auto path = (std::filesystem::temp_directory_path() / "mesh4d-test.m4d").string();
  write_m4d(mesh, path);
  EXPECT_TRUE(same(read_m4d(path), mesh));
  std::filesystem::remove(path);
}

TEST(M4d, EmptyMeshRoundTrips) {
  const Mesh4 empty;
  const auto bytes = encode_m4d(empty);
  EXPECT_TRUE(same(decode_m4d(bytes.data(), bytes.size()), empty));
}

std::string error_of(std::vector<std::uint8_t> bytes) {
  try {
    decode_m4d(bytes.data(), bytes.size());
  } catch (const MeshFormatError& e) {
    return e.what();
  }
  return "no error";
}

TEST(M4d, CorruptionTruncationAndForeignDataAreRefused) {
  const auto good = encode_m4d(small_mesh());
  auto flipped = good;
  flipped[100] ^= 0x01;
  EXPECT_NE(error_of(flipped).find("checksum"), std::string::npos);
  auto truncated = good;
  truncated.resize(good.size() - 9);
  EXPECT_NE(error_of(truncated).find("inconsistent"), std::string::npos);
  EXPECT_NE(error_of({1, 2, 3}).find("too short"), std::string::npos);
  auto foreign = good;
  foreign[0] = 'X';
  EXPECT_NE(error_of(foreign).find("magic"), std::string::npos);
  auto future = good;
  future[8] = 2;  // version 2
  EXPECT_NE(error_of(future).find("version 2"), std::string::npos);
}

TEST(M4d, OutOfRangeIdsAreRefusedEvenWithAValidChecksum) {
  auto bytes = encode_m4d(small_mesh());
  // First pentatope's first vertex id: after the header, 6 vertices (192 B), 6 kinds padded (8).
  const std::size_t at = 64 + 6 * 32 + 8;
  bytes[at] = 99;
  const auto digest = sha256(bytes.data(), bytes.size() - 32);
  std::copy(digest.begin(), digest.end(), bytes.end() - 32);
  EXPECT_NE(error_of(bytes).find("out of range"), std::string::npos);
}

void resign(std::vector<std::uint8_t>& bytes) {
  const auto digest = sha256(bytes.data(), bytes.size() - 32);
  std::copy(digest.begin(), digest.end(), bytes.end() - 32);
}

TEST(M4d, APeriodicMeshKeepsItsPeriodAndTwins) {
  const Mesh4 mesh = periodic_kuhn_box(2, 3, 4);
  const auto bytes = encode_m4d(mesh);
  EXPECT_EQ(bytes[12], kPeriodicTimeFlag);
  const Mesh4 back = decode_m4d(bytes.data(), bytes.size());
  EXPECT_TRUE(same(back, mesh));
  EXPECT_EQ(back.period_start, 0.0);
  EXPECT_EQ(back.period, 3.0);
  EXPECT_EQ(back.periodic_twins, mesh.periodic_twins);
  // The periodic section: period start, period, twin count, then the twins (8 bytes each).
  const std::size_t twins_at = bytes.size() - 32 - 8 * 8;
  auto apart = bytes;
  apart[twins_at] = 25;  // the first twin's later vertex: the corner (2, 0, 0, 3)
  resign(apart);
  EXPECT_NE(error_of(apart).find("not one period apart"), std::string::npos) << error_of(apart);
  auto count = bytes;
  count[twins_at - 8] = 9;
  resign(count);
  EXPECT_NE(error_of(count).find("inconsistent"), std::string::npos) << error_of(count);
  auto period = bytes;
  period[twins_at - 9] = 0xFF;  // the period's top byte: a NaN
  period[twins_at - 10] = 0xFF;
  resign(period);
  EXPECT_NE(error_of(period).find("period"), std::string::npos) << error_of(period);
  auto unknown = bytes;
  unknown[12] = 3;  // a flag beyond periodic time
  resign(unknown);
  EXPECT_NE(error_of(unknown).find("flags 0x2"), std::string::npos) << error_of(unknown);
  auto open = bytes;
  open[12] = 0;  // the periodic section is then bytes the counts do not account for
  resign(open);
  EXPECT_NE(error_of(open).find("inconsistent"), std::string::npos) << error_of(open);
  Mesh4 wrong = mesh;
  wrong.periodic_twins[0] = {8, 0};  // the later vertex before the period's end
  EXPECT_THROW(encode_m4d(wrong), std::invalid_argument);
}

TEST(M4d, InconsistentMeshIsNotWritten) {
  Mesh4 bad = small_mesh();
  bad.labels[1] = 0;
  EXPECT_THROW(encode_m4d(bad), std::invalid_argument);
  bad = small_mesh();
  bad.pentatopes[0][2] = 17;
  EXPECT_THROW(encode_m4d(bad), std::invalid_argument);
}

TEST(MeshStats, CountsAndDistributions) {
  const MeshStats s = compute_stats(small_mesh());
  EXPECT_EQ(s.vertices, 6u);
  EXPECT_EQ(s.pentatopes, 2u);
  EXPECT_EQ(s.boundary_tetrahedra, 3u);
  EXPECT_DOUBLE_EQ(s.shortest_edge, 1.0);
  EXPECT_GT(s.normalized_volume.min, 0);
  EXPECT_LE(s.normalized_volume.max, 1);
  EXPECT_GE(s.radius_edge_ratio.min, std::sqrt(0.4) - 1e-12);  // the regular pentatope's value
  std::uint64_t total = 0;
  for (auto c : s.normalized_volume_histogram) total += c;
  EXPECT_EQ(total, 2u);
  EXPECT_EQ(s.normalized_volume_histogram.size(), std::size_t(kHistogramBins));
}

TEST(MeshStats, ThreadsGiveTheSameCountsExtremesAndHistogram) {
  // 100,000 random pentatopes: shares of 4,096 or more, so 4 threads make 4 parts.
  Mesh4 mesh;
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> coordinate(0, 10);
  for (int i = 0; i < 2000; ++i)
    mesh.vertices.push_back({coordinate(rng), coordinate(rng), coordinate(rng), coordinate(rng)});
  std::uniform_int_distribution<std::uint32_t> vertex(0, 1999);
  for (int k = 0; k < 100000; ++k) {
    std::array<std::uint32_t, 5> p;
    for (auto& v : p) v = vertex(rng);
    if (std::set<std::uint32_t>(p.begin(), p.end()).size() == 5) mesh.pentatopes.push_back(p);
  }
  const MeshStats one = compute_stats(mesh, 1);
  const MeshStats four = compute_stats(mesh, 4);
  ASSERT_GT(one.pentatopes, 90000u);
  EXPECT_EQ(four.pentatopes, one.pentatopes);
  EXPECT_EQ(four.shortest_edge, one.shortest_edge);
  EXPECT_EQ(four.normalized_volume_histogram, one.normalized_volume_histogram);
  for (const auto& [a, b] : {std::pair{one.radius_edge_ratio, four.radius_edge_ratio},
                             std::pair{one.normalized_volume, four.normalized_volume}}) {
    EXPECT_EQ(b.min, a.min);
    EXPECT_EQ(b.max, a.max);
    EXPECT_NEAR(b.mean, a.mean, 1e-12 * std::abs(a.mean));
    EXPECT_NEAR(b.stddev, a.stddev, 1e-9 * a.stddev);
    EXPECT_GT(a.stddev, 0);
  }
}

TEST(BoundaryCheck, OnePentatopeIsClosedAndTheSmallMeshIsNot) {
  Mesh4 one;
  one.vertices = {{0, 0, 0, 0}, {1, 0, 0, 0}, {0, 1, 0, 0}, {0, 0, 1, 0}, {0, 0, 0, 1}};
  one.vertex_kinds.assign(5, VertexKind::feature);
  one.pentatopes = {{0, 1, 2, 3, 4}};
  one.labels = {1};
  for (int skip = 0; skip < 5; ++skip) {
    BoundaryTetrahedron b{{}, 0, 1, 0};
    for (int k = 0, n = 0; k < 5; ++k)
      if (k != skip) b.vertices[n++] = k;
    one.boundary.push_back(b);
  }
  const BoundaryCheck closed = check_boundary(one);
  EXPECT_EQ(closed.triangles, 10u);  // each triangle of a pentatope lies in two of its facets
  EXPECT_EQ(closed.odd, 0u);
  EXPECT_EQ(closed.pinched, 0u);
  EXPECT_EQ(closed.non_feature_uses, 0u);

  const BoundaryCheck open = check_boundary(small_mesh());
  EXPECT_GT(open.odd, 0u);
  EXPECT_GT(open.non_feature_uses, 0u);  // vertex 4 is free, vertex 0 a box corner
}

}  // namespace
}  // namespace mesh4d::mesh
