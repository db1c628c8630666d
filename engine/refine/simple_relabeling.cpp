#include "refine/simple_relabeling.h"

#include <algorithm>
#include <array>
#include <bit>
#include <utility>
#include <vector>

#include "mesh/periodic_mesh.h"

namespace mesh4d::refine {

namespace {

constexpr int kPasses = 8;  // chains of moves that each open the next are short
constexpr std::uint32_t kNoPentatope = ~std::uint32_t{0};
constexpr unsigned kAllVertices = 0x1f;

// The pentatopes (or boundary tetrahedra) around each wanted (glued) vertex, in compressed
// rows; the others' rows are empty. Only the asked pentatopes' vertices are wanted: on the
// patients they are a few thousand of the mesh's tens of thousands.
struct Stars {
  std::vector<std::uint32_t> first, items;

  template <class Cells, class Take>
  Stars(const Cells& cells, const std::vector<char>& wanted,
        const std::vector<std::uint32_t>& glued, const Take& take) {
    first.assign(wanted.size() + 1, 0);
    for (const auto& c : cells)
      if (take(c))
        for (std::uint32_t v : vertices_of(c))
          if (wanted[glued[v]]) ++first[glued[v] + 1];
    for (std::size_t v = 1; v < first.size(); ++v) first[v] += first[v - 1];
    items.resize(first.back());
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t i = 0; i < cells.size(); ++i)
      if (take(cells[i]))
        for (std::uint32_t v : vertices_of(cells[i]))
          if (wanted[glued[v]]) items[fill[glued[v]]++] = i;
  }

  static const std::array<std::uint32_t, 5>& vertices_of(const std::array<std::uint32_t, 5>& p) {
    return p;
  }
  static const std::array<std::uint32_t, 4>& vertices_of(const mesh::BoundaryTetrahedron& b) {
    return b.vertices;
  }
};

class SimpleRelabeling {
 public:
  SimpleRelabeling(mesh::Mesh4& mesh, const std::vector<std::uint32_t>& asked)
      : mesh_(mesh),
        glued_(mesh::glued_vertex_ids(mesh)),
        wanted_(vertices_of(asked)),
        stars_(mesh.pentatopes, wanted_, glued_, [](const auto&) { return true; }),
        outside_(mesh.boundary, wanted_, glued_,
                 [](const mesh::BoundaryTetrahedron& b) { return b.outer == 0; }),
        held_(mesh.pentatopes.size(), 0) {}

  // Whether p may move from its label to `to` (the header's condition). held_[q] collects, as
  // bits of p's vertices, the face p shares with each pentatope q around it; outer, the faces
  // it shares with the outside.
  bool simple(std::uint32_t p, mesh::Label to) {
    const mesh::Label from = mesh_.labels[p];
    around_.clear();
    outer_.clear();
    const auto& cell = mesh_.pentatopes[p];
    for (int k = 0; k < 5; ++k) {
      const std::uint32_t g = glued_[cell[k]];
      for (std::uint32_t i = stars_.first[g]; i < stars_.first[g + 1]; ++i) {
        const std::uint32_t q = stars_.items[i];
        if (q == p) continue;
        if (held_[q] == 0) around_.push_back(q);
        held_[q] |= 1u << k;
      }
      for (std::uint32_t i = outside_.first[g]; i < outside_.first[g + 1]; ++i)
        outer_.push_back(face_of(cell, mesh_.boundary[outside_.items[i]].vertices));
    }
    unsigned gains = 0, loses = 0;  // the facets shared with `to`, with `from`
    neighbors_.fill(kNoPentatope);
    for (std::uint32_t q : around_)
      if (std::popcount(held_[q]) == 4) {
        const unsigned facet = ~held_[q] & kAllVertices;  // named by the vertex it leaves out
        neighbors_[std::countr_zero(facet)] = q;
        if (mesh_.labels[q] == to) gains |= facet;
        if (mesh_.labels[q] == from) loses |= facet;
      }
    // A face lies in one of `facets` when a vertex that one leaves out is not in the face.
    const auto within = [](unsigned face, unsigned facets) { return (~face & facets) != 0; };
    bool ok = gains != 0 && loses != 0;
    // `to` gains a 4-ball along a 3-ball: every face it touches lies in a facet it shares.
    // `from` gives up a 4-ball whose part on its boundary is a 3-ball: every face that anything
    // else (another label, the outside) touches lies in a facet not shared with `from`.
    const unsigned rest = kAllVertices & ~loses;
    for (std::uint32_t q : around_) {
      if (!ok) break;
      if (mesh_.labels[q] == to) ok = within(held_[q], gains);
      if (ok && mesh_.labels[q] != from) ok = within(held_[q], rest);
    }
    for (unsigned face : outer_) ok = ok && within(face, rest);
    for (std::uint32_t q : around_) held_[q] = 0;
    return ok;
  }

  std::size_t run(std::vector<std::uint32_t> asked,
                  const std::function<mesh::Label(std::uint32_t)>& target) {
    std::vector<char> changed(mesh_.pentatopes.size(), 0);
    std::size_t moved = 0;
    for (int pass = 0; pass < kPasses && !asked.empty(); ++pass) {
      std::vector<std::uint32_t> refused;
      const std::size_t before = moved;
      for (std::uint32_t p : asked) {
        const mesh::Label to = target(p);
        if (to == 0 || to == mesh_.labels[p]) continue;
        if (!simple(p, to)) {
          refused.push_back(p);
          continue;
        }
        mesh_.labels[p] = to;
        if (!changed[p]) moves_.push_back({p, neighbors_});
        changed[p] = 1;
        ++moved;
      }
      if (moved == before) break;
      asked.swap(refused);
    }
    if (moved > 0) rebuild_boundary(changed);
    moves_.clear();
    return moved;
  }

 private:
  // The boundary tetrahedra made again on both sides of each facet of a moved pentatope; the
  // rest are kept. Extraction lists them by pentatope, then by the vertex each facet leaves
  // out, and so does this.
  void rebuild_boundary(const std::vector<char>& changed) {
    // The facets of the moved pentatopes, on their unmoved neighbors' side: (neighbor, the
    // vertex of the neighbor the facet leaves out).
    std::vector<std::pair<std::uint32_t, int>> redone;
    std::vector<mesh::BoundaryTetrahedron> made;
    const auto add = [&](std::uint32_t p, int i, mesh::Label other) {
      if (other == mesh_.labels[p]) return;
      mesh::BoundaryTetrahedron t;
      for (int k = 0, m = 0; k < 5; ++k)
        if (k != i) t.vertices[m++] = mesh_.pentatopes[p][k];
      t.pentatope = p;
      t.inner = mesh_.labels[p];
      t.outer = other;
      made.push_back(t);
    };
    for (const Move& move : moves_)
      for (int i = 0; i < 5; ++i) {
        const std::uint32_t q = move.neighbors[i];
        add(move.pentatope, i, q == kNoPentatope ? 0 : mesh_.labels[q]);
        if (q == kNoPentatope || changed[q]) continue;
        const int j = left_out(q, move.pentatope);
        redone.push_back({q, j});
        add(q, j, mesh_.labels[move.pentatope]);
      }
    std::sort(redone.begin(), redone.end());
    std::vector<mesh::BoundaryTetrahedron>& boundary = mesh_.boundary;
    std::erase_if(boundary, [&](const mesh::BoundaryTetrahedron& b) {
      if (changed[b.pentatope]) return true;
      if (!wanted_[glued_[b.vertices[0]]] && !wanted_[glued_[b.vertices[1]]]) return false;
      const std::pair<std::uint32_t, int> key{b.pentatope, left_out(b)};
      return std::binary_search(redone.begin(), redone.end(), key);
    });
    boundary.insert(boundary.end(), made.begin(), made.end());
    std::vector<std::uint32_t> order(boundary.size());
    for (std::uint32_t i = 0; i < order.size(); ++i)
      order[i] = boundary[i].pentatope * 5 + static_cast<std::uint32_t>(left_out(boundary[i]));
    std::vector<std::uint32_t> index(boundary.size());
    for (std::uint32_t i = 0; i < index.size(); ++i) index[i] = i;
    std::sort(index.begin(), index.end(),
              [&](std::uint32_t a, std::uint32_t b) { return order[a] < order[b]; });
    std::vector<mesh::BoundaryTetrahedron> sorted(boundary.size());
    for (std::uint32_t i = 0; i < index.size(); ++i) sorted[i] = boundary[index[i]];
    boundary.swap(sorted);
  }

  // Which vertex of pentatope q (its index there) pentatope p does not have.
  int left_out(std::uint32_t q, std::uint32_t p) const {
    for (int k = 0; k < 5; ++k) {
      const std::uint32_t g = glued_[mesh_.pentatopes[q][k]];
      bool in = false;
      for (std::uint32_t v : mesh_.pentatopes[p]) in = in || glued_[v] == g;
      if (!in) return k;
    }
    return 0;
  }
  // Which vertex of its pentatope a boundary tetrahedron leaves out.
  int left_out(const mesh::BoundaryTetrahedron& b) const {
    const auto& cell = mesh_.pentatopes[b.pentatope];
    for (int k = 0; k < 5; ++k)
      if (std::find(b.vertices.begin(), b.vertices.end(), cell[k]) == b.vertices.end()) return k;
    return 0;
  }

  // Which (glued) vertices the asked pentatopes have.
  std::vector<char> vertices_of(const std::vector<std::uint32_t>& asked) const {
    std::vector<char> wanted(mesh_.vertices.size(), 0);
    for (std::uint32_t p : asked)
      for (std::uint32_t v : mesh_.pentatopes[p]) wanted[glued_[v]] = 1;
    return wanted;
  }

  // The face of `cell` that `vertices` share with it, as bits of the cell's vertices.
  unsigned face_of(const std::array<std::uint32_t, 5>& cell,
                   const std::array<std::uint32_t, 4>& vertices) const {
    unsigned face = 0;
    for (int k = 0; k < 5; ++k)
      for (std::uint32_t v : vertices)
        if (glued_[v] == glued_[cell[k]]) face |= 1u << k;
    return face;
  }

  mesh::Mesh4& mesh_;
  std::vector<std::uint32_t> glued_;
  std::vector<char> wanted_;  // by glued vertex: a vertex of an asked pentatope (stars_ has it)
  Stars stars_;
  Stars outside_;                   // by glued vertex: its boundary tetrahedra against the outside
  std::vector<std::uint8_t> held_;  // by pentatope: the face it shares with the one asked
  std::vector<std::uint32_t> around_;       // the pentatopes held_ is set for
  std::vector<unsigned> outer_;             // the faces the asked one shares with the outside
  std::array<std::uint32_t, 5> neighbors_;  // across each facet of the pentatope simple() saw
  struct Move {
    std::uint32_t pentatope;
    std::array<std::uint32_t, 5> neighbors;  // across its facets, kNoPentatope: the outside
  };
  std::vector<Move> moves_;
};

}  // namespace

std::size_t relabel_simple(mesh::Mesh4& mesh,
                           const std::function<mesh::Label(std::uint32_t)>& target) {
  std::vector<std::uint32_t> asked;
  for (std::uint32_t p = 0; p < mesh.pentatopes.size(); ++p) {
    const mesh::Label to = target(p);
    if (to != 0 && to != mesh.labels[p]) asked.push_back(p);
  }
  if (asked.empty()) return 0;
  return SimpleRelabeling(mesh, asked).run(std::move(asked), target);
}

}  // namespace mesh4d::refine
