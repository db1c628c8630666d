// Extraction: the output mesh from the final triangulation, on the job's threads. The output is
// the finite pentatopes whose circumcenter lies inside a label, tagged with it, in cell order;
// their vertices in vertex-id order; and the boundary tetrahedra (facets between a kept
// pentatope and a neighbor of another label, or none) in the order of their pentatopes. In
// periodic time, the representatives only, with the twins of the vertices past the period.
#include "refine/extraction.h"

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <utility>

#include "support/parallel_parts.h"

namespace mesh4d::refine {

using delaunay::CellId;
using delaunay::VertexKind;

namespace {

constexpr std::uint32_t kUnset = 0xFFFFFFFFu;
constexpr std::size_t kMinShare = 8192;  // cell slots per thread, at least

mesh::VertexKind output_kind(VertexKind k) {
  return k == VertexKind::feature ? mesh::VertexKind::feature
         : k == VertexKind::box   ? mesh::VertexKind::box
                                  : mesh::VertexKind::free;
}

}  // namespace

mesh::Mesh4 extract(const RefinementState& state, std::vector<std::string>& warnings) {
  const auto& st = state.tri.store();
  const std::size_t slots = st.cell_slots();
  const unsigned parts = support::parts_for(slots, kMinShare, working_threads(state.params));

  // Pass 1, by shares of the cell slots: every pentatope's label, which are kept, and which
  // vertices they use (several threads may mark one vertex: atomic stores of the same value).
  std::vector<domain::Label> label(slots, 0);
  std::vector<std::uint8_t> kept_cell(slots, 0);
  std::vector<std::uint8_t> used(st.vertex_slots(), 0);
  std::vector<std::size_t> first(parts + 1, 0);  // output index of each share's first pentatope
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(slots, part, parts);
    std::size_t kept = 0;
    for (CellId c = static_cast<CellId>(begin); c < end; ++c) {
      if (!st.is_live(c) || st.is_infinite(c) || !state.info[c].finite) continue;
      label[c] = state.label_of(c);
      // In periodic time only each class's representative is output; its label is the one its
      // neighbours see in every sheet.
      if (label[c] == 0 || !state.covering.representative(state.tri, c)) continue;
      ++kept;
      kept_cell[c] = 1;
      for (VertexId v : st.cell(c).v) std::atomic_ref(used[v]).store(1, std::memory_order_relaxed);
    }
    first[part + 1] = kept;
  });
  for (unsigned p = 0; p < parts; ++p) first[p + 1] += first[p];

  // In periodic time, a vertex past the middle sheet is glued to its twin one period earlier,
  // which the mesh then holds too.
  std::vector<std::pair<VertexId, VertexId>> twins;  // (past the period, one period earlier)
  if (state.covering.active()) {
    for (VertexId v = 0; v < st.vertex_slots(); ++v) {
      if (!used[v] || state.covering.in_middle(st.point(v)[3])) continue;
      const VertexId e = state.covering.twin(state.tri, v, -1);
      if (e == delaunay::kNoVertex)
        throw std::logic_error("Refiner: a vertex past the period has no twin one period earlier");
      twins.emplace_back(v, e);
      used[e] = 1;
    }
  }

  // The vertices, numbered in id order (one pass over a byte per vertex).
  mesh::Mesh4 mesh;
  std::vector<std::uint32_t> vertex_index(st.vertex_slots(), kUnset);
  for (VertexId v = 0; v < st.vertex_slots(); ++v) {
    if (!used[v]) continue;
    vertex_index[v] = static_cast<std::uint32_t>(mesh.vertices.size());
    mesh.vertices.push_back(st.point(v));
    mesh.vertex_kinds.push_back(output_kind(st.vertex(v).kind));
  }

  // Pass 2, the same shares: the pentatopes in their places, and each share's boundary
  // tetrahedra, joined in share order afterwards.
  mesh.pentatopes.resize(first[parts]);
  mesh.labels.resize(first[parts]);
  std::vector<std::vector<mesh::BoundaryTetrahedron>> boundary(parts);
  support::run_parts(parts, [&](unsigned part) {
    const auto [begin, end] = support::part_range(slots, part, parts);
    std::size_t out = first[part];
    for (CellId c = static_cast<CellId>(begin); c < end; ++c) {
      if (!kept_cell[c]) continue;
      const auto& cell = st.cell(c);
      const auto index = static_cast<std::uint32_t>(out++);
      for (int i = 0; i < 5; ++i) mesh.pentatopes[index][i] = vertex_index[cell.v[i]];
      mesh.labels[index] = label[c];
      for (int i = 0; i < 5; ++i) {
        const CellId n = cell.n[i];
        const domain::Label other = st.is_infinite(n) ? 0 : label[n];
        if (other == label[c]) continue;
        mesh::BoundaryTetrahedron b;
        for (int k = 0, m = 0; k < 5; ++k)
          if (k != i) b.vertices[m++] = vertex_index[cell.v[k]];
        b.pentatope = index;
        b.inner = label[c];
        b.outer = other;
        boundary[part].push_back(b);
      }
    }
  });
  for (const auto& share : boundary)
    mesh.boundary.insert(mesh.boundary.end(), share.begin(), share.end());
  if (state.covering.active()) {
    mesh.period_start = state.covering.period().start;
    mesh.period = state.covering.period().length;
    for (const auto& [later, earlier] : twins)
      mesh.periodic_twins.push_back({vertex_index[later], vertex_index[earlier]});
  }

  if (mesh.pentatopes.empty())
    warnings.push_back(
        "no pentatope has its circumcenter inside the object: delta may be too "
        "large for this image");
  return mesh;
}

}  // namespace mesh4d::refine
