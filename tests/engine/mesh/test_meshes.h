// Small 4D meshes for the mesh module's tests, known exactly.
#pragma once

#include <algorithm>
#include <array>
#include <map>
#include <vector>

#include "mesh/mesh4.h"

namespace mesh4d::mesh {

// The box [0,sx]×[0,sy]×[0,sz]×[0,1] as 24 Kuhn simplices (one per order of the axes), label 1.
inline Mesh4 kuhn_box(double sx, double sy, double sz) {
  Mesh4 m;
  for (int c = 0; c < 16; ++c) {
    m.vertices.push_back(
        {(c & 1) * sx, ((c >> 1) & 1) * sy, ((c >> 2) & 1) * sz, double((c >> 3) & 1)});
    m.vertex_kinds.push_back(VertexKind::free);
  }
  std::array<int, 4> axes{0, 1, 2, 3};
  do {
    std::array<std::uint32_t, 5> p{};
    std::uint32_t corner = 0;
    for (int k = 0; k < 4; ++k) p[k + 1] = corner |= 1u << axes[k];
    m.pentatopes.push_back(p);
    m.labels.push_back(1);
  } while (std::next_permutation(axes.begin(), axes.end()));
  return m;
}

// `layers` kuhn_boxes stacked in time, in periodic time over [0, layers): the corners at
// t = layers glued to those at t = 0 (a period of one layer would glue a pentatope's own
// corners).
inline Mesh4 periodic_kuhn_box(double sx, double sy, double sz, int layers = 3) {
  const Mesh4 box = kuhn_box(sx, sy, sz);
  Mesh4 m;
  for (int layer = 0; layer <= layers; ++layer)
    for (std::uint32_t c = 0; c < 8; ++c) {
      Point4 p = box.vertices[c];
      p[3] = layer;
      m.vertices.push_back(p);
      m.vertex_kinds.push_back(VertexKind::free);
    }
  for (int layer = 0; layer < layers; ++layer)
    for (auto p : box.pentatopes) {
      for (std::uint32_t& v : p) v = (v & 7) + 8 * static_cast<std::uint32_t>(layer + (v >> 3));
      m.pentatopes.push_back(p);
      m.labels.push_back(1);
    }
  m.period_start = 0;
  m.period = layers;
  for (std::uint32_t c = 0; c < 8; ++c)
    m.periodic_twins.push_back({8 * static_cast<std::uint32_t>(layers) + c, c});
  return m;
}

// Each facet (sorted) and the pentatopes it belongs to.
inline std::map<std::array<std::uint32_t, 4>, std::vector<std::uint32_t>> facet_owners(
    const Mesh4& m) {
  std::map<std::array<std::uint32_t, 4>, std::vector<std::uint32_t>> owners;
  for (std::uint32_t i = 0; i < m.pentatopes.size(); ++i)
    for (int skip = 0; skip < 5; ++skip) {
      std::array<std::uint32_t, 4> f;
      for (int k = 0, j = 0; k < 5; ++k)
        if (k != skip) f[j++] = m.pentatopes[i][k];
      std::sort(f.begin(), f.end());
      owners[f].push_back(i);
    }
  return owners;
}

inline void add_hull(Mesh4& m) {
  for (const auto& [f, o] : facet_owners(m))
    if (o.size() == 1) m.boundary.push_back({f, o[0], m.labels[o[0]], 0});
}

// The facets between two labels, from both sides, as the refiner lists them.
inline void add_interfaces(Mesh4& m) {
  for (const auto& [f, o] : facet_owners(m))
    if (o.size() == 2 && m.labels[o[0]] != m.labels[o[1]])
      for (int side = 0; side < 2; ++side)
        m.boundary.push_back({f, o[side], m.labels[o[side]], m.labels[o[1 - side]]});
}

}  // namespace mesh4d::mesh
