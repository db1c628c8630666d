#include "refine/translate_labels.h"

#include <sstream>
#include <vector>

#include "refine/periodic_covering.h"

namespace mesh4d::refine {

TranslateLabels compare_translate_labels(const RefinementState& state) {
  TranslateLabels out;
  if (!state.covering.active()) return out;
  const auto& st = state.tri.store();
  std::vector<delaunay::CellId> twins;
  for (delaunay::CellId c = 0; c < st.cell_slots(); ++c) {
    if (!st.is_live(c) || st.is_infinite(c) || !state.covering.representative(state.tri, c))
      continue;
    ++out.representatives;
    state.covering.twin_cells(state.tri, c, twins);
    const domain::Label own = state.output_label(c);
    for (delaunay::CellId t : twins) {
      ++out.translates;
      const domain::Label other = state.output_label(t);
      if (other == own) continue;
      if (out.mismatched++ == 0) {
        std::ostringstream s;
        s << "pentatope " << c << " (anchor t " << PeriodicCovering::anchor(state.tri, c)
          << ", radius " << state.info[c].radius << ") has label " << int{own} << ", its translate "
          << t << " (anchor t " << PeriodicCovering::anchor(state.tri, t) << ") label "
          << int{other};
        out.first = s.str();
      }
    }
  }
  return out;
}

}  // namespace mesh4d::refine
