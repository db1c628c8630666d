// The refiner's questions to the image (docs/algorithm.md, "Input and the domain"): which label is
// at x, where the hyper-surface ∂Ω crosses a segment, and which point of ∂Ω is closest to x (cfp).
//
// The label function: for each label L, I_L(x) is the multilinear interpolation (16 voxel
// centers around x) of the indicator "voxel has label L", with background outside the image,
// plus a small offset β_L that grows with the label's rank; the label at x is the L with the
// largest I_L(x) + β_L (the smaller label on an exact tie). ∂Ω is where that choice changes:
// between labels A and B it is the zero set of the cut function f_AB = I_A + β_A − I_B − β_B.
// Multi-label images therefore have label–label interfaces as surfaces too.
//
// Why the offsets: binary labels interpolated without them tie exactly at every "checkerboard"
// face (A and B on the diagonals of a 2×2 square of voxels), where the zero set is two sheets
// crossing, not a manifold; no mesh can follow it without pinching there (on the patients,
// nine in ten pinched boundary triangles had such a face within a voxel). Offsets below 1/16
// (the smallest weight a present label can have) break every such tie the same way, higher
// labels winning, and move the interfaces by a few hundredths of a voxel.
#pragma once

#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "domain/face_components.h"
#include "domain/label_image.h"
#include "domain/time_caps.h"
#include "domain/uniform_cells.h"

namespace mesh4d::domain {

struct SurfacePoint {
  Point4 point;  // on ∂Ω: |I_inner − I_outer| at most ~1e-12 there
  Label inner;   // the label on the side the search started from
  Label outer;   // the label on the other side
};

/// A segment whose ends have different labels, label_a at a: ∂Ω crosses it.
struct SurfaceBracket {
  Point4 a, b;
  Label label_a, label_b;
  SurfacePoint middle() const;
};

class SurfaceOracle {
 public:
  /// Keeps a reference to `image` (which must outlive the oracle) and computes its feature
  /// transform. Throws ImageError when the image has a single label (no surface). With time
  /// caps (time_caps.h), a ghost label takes its real label's offset β and has no rank of its
  /// own, so that the two tie exactly on the cap's hyperplane, where they weigh alike.
  /// The feature transform runs on up to `threads` threads.
  explicit SurfaceOracle(const LabelImage4& image, const TimeCaps& caps = {}, unsigned threads = 1);

  const LabelImage4& image() const { return image_; }

  Label label_at(const Point4& x) const;
  bool inside(const Point4& x) const { return label_at(x) != 0; }
  /// f_ab(x) = I_a(x) + β_a − I_b(x) − β_b.
  double cut_value(const Point4& x, Label a, Label b) const;
  /// The largest offset β (that of the highest label); see the top of this file.
  static constexpr double kMaxLabelOffset = 0.06;
  /// β by label value, up to the highest of `labels` (ascending, as LabelImage4::labels()):
  /// by rank, 0 for the lowest, kMaxLabelOffset for the highest.
  static std::vector<double> label_offsets(const std::vector<Label>& labels);
  /// The label a time caps' ghost mirrors; any other label is its own.
  Label real_label(Label l) const;
  /// This image's offsets, by label value.
  const std::vector<double>& label_offsets() const { return offset_; }
  /// The image's pieces as the label function joins them (label_pieces.h), read once with the
  /// feature transform: the refiner matches its regions' pieces with them.
  const FacePieces& pieces() const { return pieces_; }
  /// The piece of the voxel nearest to x when that voxel has `label`, else FacePieces::kNoPiece.
  std::uint32_t piece_at(const Point4& x, Label label) const;
  /// The piece of the voxel nearest to x, whatever its label (FacePieces::kNoPiece for the
  /// background): piece_at(x, l) is this piece when its label is l.
  std::uint32_t nearest_piece(const Point4& x) const;
  /// Its gradient (central differences at a tenth of a voxel: exact but within that distance of
  /// a voxel-center hyperplane, where the piecewise multilinear f has a kink).
  Vec4 cut_gradient(const Point4& x, Label a, Label b) const;

  /// The first point from a towards b where the label changes (sampled every half voxel, then
  /// bisected to machine precision), or nothing when no change is seen.
  std::optional<SurfacePoint> first_crossing(const Point4& a, const Point4& b) const;

  /// How hard cfp works: `ray` is the paper's method (a crossing on the ray from x through the
  /// nearest surface voxel, or between that voxel and a neighbor of another label: within about
  /// a voxel of the closest point, ~10× cheaper); `descent` then moves each candidate along ∂Ω
  /// to where x − z is normal to it.
  enum class CfpMode { ray, descent };

  /// cfp(x): the closest point of ∂Ω to x (see CfpMode). If no crossing is found near the
  /// nearest surface voxel (never seen on a validated image), returns x with inner == outer:
  /// callers check that before using the point as a surface point.
  SurfacePoint closest_surface_point(const Point4& x, CfpMode mode = CfpMode::descent) const;
  /// What the oracle reads about a point before any search: its label, the nearest surface
  /// voxel to its nearest voxel (by linear index), and a lower bound on its distance to ∂Ω from
  /// that voxel alone.
  struct PointFacts {
    Label label = 0;
    std::uint32_t surface_voxel = 0;
    double lower = 0;
  };
  PointFacts facts(const Point4& x) const { return facts(x, label_at(x)); }
  /// The same for a point whose label is known (the refiner reads every circumcenter's label,
  /// but the rest only for the pentatopes it classifies, four in ten of those it makes).
  PointFacts facts(const Point4& x, Label label) const;

  /// The ray mode's answer bracketed to kRankTolerance of the smallest spacing (its middle is
  /// within half that of ∂Ω), for callers that often drop it; pinpoint() finishes the one kept.
  /// Nothing when no crossing is found near the feature voxel.
  std::optional<SurfaceBracket> closest_surface_bracket(const Point4& x) const {
    return closest_surface_bracket(x, facts(x));
  }
  /// The same, with x's facts already known.
  std::optional<SurfaceBracket> closest_surface_bracket(const Point4& x,
                                                        const PointFacts& known) const {
    return closest_surface_bracket(x, known, nullptr, nullptr);
  }
  /// What a caller that drops some answers of closest_surface_bracket() says about a segment:
  /// whether it would drop every point of it.
  class Dismissal {
   public:
    virtual bool drops(const Point4& a, const Point4& b) const = 0;

   protected:
    ~Dismissal() = default;
  };
  /// The same, for such a caller: when `dismissal` drops every place where the candidates can
  /// lie, asked before the ray's walk, as it goes, and before its crossing is halved, nothing more
  /// is done, *dropped is set and nothing returned; otherwise the same answer as without it, and
  /// *dropped is cleared.
  std::optional<SurfaceBracket> closest_surface_bracket(const Point4& x, const PointFacts& known,
                                                        const Dismissal* dismissal,
                                                        bool* dropped) const;
  SurfacePoint pinpoint(const SurfaceBracket& k) const;

  /// Whether the ray mode stops a walk whose crossing could only lose to an edge crossing (see
  /// cfp_candidates); on by default, and the answers are the same: tests turn it off to check.
  void set_ray_give_up(bool on) { ray_give_up_ = on; }

  /// How closely closest_surface_bracket() brackets its candidates (to rank them, and what it
  /// returns), in units of the smallest spacing.
  static constexpr double kRankTolerance = 1.0 / 32;

  /// Bytes held by the oracle (the feature transform and the pieces).
  std::size_t memory_bytes() const {
    return (feature_.size() + pieces_.piece.size()) * sizeof(std::uint32_t) +
           uniform_.memory_bytes();
  }

 private:
  // Interpolated indicator values of the labels around continuous index u.
  struct LabelWeights {
    Label label[16];
    double weight[16];
    int count = 0;
  };
  // The distinct labels at a voxel cell's 16 corners (corner bit k set: the upper neighbor
  // along axis k), and which of them each corner has: read once per cell, then each point in
  // the cell costs only its 16 multilinear weights.
  struct CellLabels {
    Label label[16];
    std::uint8_t slot[16];  // corner -> index in label
    int count = 0;
  };
  static CellLabels cell_labels(const Label corner_label[16]);
  LabelWeights weights_at(const Point4& x) const;
  // The weights at fractional position `frac` in a voxel cell with these labels.
  LabelWeights weights_in_cell(const CellLabels& cell, const double frac[4]) const;
  Label argmax(const LabelWeights& w) const;
  // Halves the bracket until it is shorter than `tolerance` (or the spacing of doubles).
  SurfaceBracket narrow(SurfaceBracket k, double tolerance) const;
  // The first label change from a towards b, bracketed to within `tolerance`.
  // With a `give_up` point: nothing either once a sample farther than give_up.distance from
  // give_up.from still has a's label (a ray whose crossing could only lose to a nearer one).
  struct GiveUp {
    Point4 from;
    double distance;
  };
  // With a `walk_dismissal`: nothing either, and *dropped set, once its dismissal drops the
  // rest of the walk (from a sample still of a's label to walk_dismissal.end).
  struct WalkDismissal {
    const Dismissal* dismissal;
    Point4 end;
    bool* dropped;
  };
  std::optional<SurfaceBracket> first_bracket(const Point4& a, const Point4& b, double tolerance,
                                              const Label* label_a = nullptr,
                                              const GiveUp* give_up = nullptr,
                                              const WalkDismissal* walk_dismissal = nullptr) const;
  // cfp's candidates (see CfpMode) into `out`, nearest to x first, x's side as a. Crossings on
  // voxel edges are computed (edge_bracket), or with `search_edges` found by halving.
  void cfp_starts(const Point4& x, const PointFacts& known, CfpMode mode, double tolerance,
                  std::vector<SurfaceBracket>& out, bool search_edges = false) const {
    cfp_candidates(x, known, mode, tolerance, out, search_edges, nullptr);
    rank(x, known.label, out);
  }
  // The same candidates in the order found (the ray's first). With a dismissal, false (and
  // nothing more done) once it drops every place where they can lie (see Dismissal).
  bool cfp_candidates(const Point4& x, const PointFacts& known, CfpMode mode, double tolerance,
                      std::vector<SurfaceBracket>& out, bool search_edges,
                      const Dismissal* dismissal) const;
  // Orients every candidate with x's side (label x_label) as a, then sorts them nearest first.
  static void rank(const Point4& x, Label x_label, std::vector<SurfaceBracket>& candidates);
  // The edges from surface voxel sc (center `center`) to its face neighbors of another label,
  // as brackets with sc's side as a; returns how many (at least one for a surface voxel).
  int voxel_edges(const std::uint32_t sc[4], const Point4& center, SurfaceBracket out[8]) const;
  // The nearest voxel to x (clamped to the image), by linear index, and its center (when asked).
  std::size_t nearest_voxel(const Point4& x, Point4* center) const;
  // A voxel's center from its linear index (below 2^32, as in the feature transform).
  Point4 center_of(std::uint32_t voxel, std::uint32_t coordinates[4]) const;
  // The crossing on the segment between two neighboring voxel centers of different labels,
  // bracketed to `tolerance` where the cut function vanishes (computed, not searched).
  SurfaceBracket edge_bracket(const SurfaceBracket& edge, double tolerance) const;
  // The tolerance of every surface point returned: 1e-11 of the smallest spacing, where
  // |f| ≤ 2e-11 (f changes by at most 2 per voxel along any axis).
  double fine_tolerance() const { return 1e-11 * min_spacing_; }
  std::optional<SurfacePoint> project_along(const Point4& seed, const Vec4& normal) const;
  void refine_towards(const Point4& x, SurfacePoint& z) const;

  double offset(Label l) const { return l < offset_.size() ? offset_[l] : 0; }

  const LabelImage4& image_;
  std::vector<std::uint32_t> feature_;
  UniformCells uniform_;
  std::vector<double> offset_;  // β by label value
  std::vector<Label> real_of_;  // the time caps' (TimeCaps::real_of)
  FacePieces pieces_;
  std::size_t corner_offset_[16];  // linear index of each of a cell's corners from its first
  double voxel_size_;              // the largest spacing: the scale of search steps
  double min_spacing_;             // the smallest: the scale of tolerances
  double cell_diagonal_;           // of the hypercube between 16 voxel centers
  bool ray_give_up_ = true;
  bool border_background_ = false;  // every voxel on the image's outer layer is background
};

}  // namespace mesh4d::domain
