// The time caps' ghosts are dropped after refinement, their pentatopes outside as the
// background's (time_caps.h): the stages that keep the regions' topology (the manifold scan, the
// pinch scan, the piece matching) look at the output's regions only. A region pinched at a
// vertex or a triangle is found when it is a real label's and left alone when it is a ghost's.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "domain/surface_oracle.h"
#include "domain/time_caps.h"
#include "refine/manifold_scan.h"
#include "refine/pinch_scan.h"
#include "refine/refine_checks.h"
#include "refine/refinement_state.h"

namespace mesh4d::refine {
namespace {

using delaunay::CellId;
using domain::Label;

class GhostRegions : public ::testing::Test {
 protected:
  GhostRegions()
      : image_(capped(small_ventricle(), &caps_)),
        oracle_(image_, caps_),
        state_(oracle_, params()) {
    // A Delaunay triangulation of random points in the box, every pentatope outside.
    state_.insert_box();
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> unit(0.2, 0.8);
    for (int i = 0; i < 300; ++i) {
      Point4 p;
      for (int k = 0; k < 4; ++k)
        p[k] = state_.box[0][k] + unit(rng) * (state_.box[1][k] - state_.box[0][k]);
      state_.tri.insert(p);
    }
    const auto& st = state_.tri.store();
    std::vector<CellId> live;
    for (CellId c = 0; c < st.cell_slots(); ++c)
      if (st.is_live(c)) live.push_back(c);
    state_.admit(live);
    for (CellId c : live)
      if (state_.info[c].finite) state_.set_label(c, 0);
  }

  static RefineParams params() {
    RefineParams p;
    p.delta = 8;
    return p;
  }

  static domain::LabelImage4 capped(const domain::LabelImage4& image, domain::TimeCaps* caps) {
    std::string warning;
    domain::LabelImage4 out = domain::add_time_caps(image, 1, caps, &warning);
    domain::validate_and_close(out);
    return out;
  }

  Label ghost_of(Label real) const {
    for (Label g = 0; g < caps_.real_of.size(); ++g)
      if (caps_.real_of[g] == real) return g;
    return 0;
  }

  // Two finite pentatopes of one vertex's star that share exactly `shared` vertices, the
  // vertex among them.
  std::pair<CellId, CellId> sharing(std::size_t shared, mesh4d::VertexId* v) {
    const auto& st = state_.tri.store();
    std::vector<CellId> star;
    for (mesh4d::VertexId u = 0; u < st.vertex_slots(); ++u) {
      if (st.vertex(u).kind != delaunay::VertexKind::free) continue;
      state_.tri.incident_cells(u, star);
      for (CellId a : star)
        for (CellId b : star) {
          if (a >= b || !state_.info[a].finite || !state_.info[b].finite) continue;
          std::size_t common = 0;
          for (mesh4d::VertexId x : st.cell(a).v)
            common += std::count(std::begin(st.cell(b).v), std::end(st.cell(b).v), x);
          if (common == shared) return *v = u, std::pair{a, b};
        }
    }
    ADD_FAILURE() << "no two pentatopes share " << shared << " vertices";
    return {0, 0};
  }

  domain::TimeCaps caps_;
  domain::LabelImage4 image_;
  domain::SurfaceOracle oracle_;
  RefinementState state_;
};

TEST_F(GhostRegions, AVertexPinchIsFoundInARealRegionOnly) {
  mesh4d::VertexId v = 0;
  const auto [a, b] = sharing(1, &v);
  for (const Label l : {Label{1}, ghost_of(1)}) {
    ASSERT_NE(l, 0);
    state_.set_label(a, l), state_.set_label(b, l);
    const std::vector<NonManifoldVertex> found = find_non_manifold_vertices(state_);
    const bool at_v = std::any_of(found.begin(), found.end(), [&](const NonManifoldVertex& f) {
      return f.vertex == v && f.label == l;
    });
    EXPECT_EQ(at_v, l == 1) << "label " << l;
    if (l != 1) {
      EXPECT_TRUE(found.empty());
    }
  }
}

TEST_F(GhostRegions, ATrianglePinchIsCountedInARealRegionOnly) {
  mesh4d::VertexId v = 0;
  const auto [a, b] = sharing(3, &v);
  for (const Label l : {Label{2}, ghost_of(2)}) {
    ASSERT_NE(l, 0);
    state_.set_label(a, l), state_.set_label(b, l);
    std::vector<PinchedTriangle> pinched;
    PinchScan(state_).count(&pinched);
    EXPECT_EQ(pinched.size(), l == 2 ? 1u : 0u) << "label " << l;
  }
}

}  // namespace
}  // namespace mesh4d::refine
