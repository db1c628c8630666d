#include "domain/segmentation_cleanup.h"

#include <algorithm>
#include <map>
#include <numeric>
#include <sstream>

#include "domain/face_components.h"

namespace mesh4d::domain {

std::vector<std::string> CleanupReport::warnings(std::size_t min_voxels) const {
  std::vector<std::string> out;
  for (const PerLabel& l : labels) {
    std::ostringstream s;
    s << "segmentation cleanup: label " << l.label << ": " << l.pieces
      << (l.label == 0 ? " holes of background filled (" : " islands removed (") << l.voxels
      << " voxels in pieces under " << min_voxels << " voxels; min_island_voxels = 0 keeps them)";
    out.push_back(s.str());
  }
  for (const auto& [label, d] : diagonal.labels) {
    if (d.contacts == 0 && d.left == 0) continue;
    std::ostringstream s;
    s << "segmentation cleanup: label " << label << ": " << d.contacts
      << " diagonal contacts that the label function joins made face contacts (" << d.voxels
      << " voxels took the label)";
    if (d.left) s << "; " << d.left << " could not be without splitting another label";
    out.push_back(s.str());
  }
  return out;
}

namespace {

// How many of voxel i's faces lie on the image's border.
std::size_t border_faces(const Dims4& d, std::size_t i) {
  std::size_t faces = 0;
  for (int a = 0; a < 4; ++a) {
    const std::size_t c = i % d[a];
    i /= d[a];
    faces += (c == 0) + (c + 1 == d[a]);
  }
  return faces;
}

// Every face-connected piece below min_voxels to the label most of its face neighbors have.
void remove_small_pieces(LabelImage4& image, std::size_t min_voxels, CleanupReport& report,
                         unsigned threads) {
  const FacePieces found = face_pieces(image, true, threads);
  // The small pieces' voxels, grouped by piece, smallest pieces first.
  std::vector<std::uint32_t> small;
  for (std::uint32_t p = 0; p < found.pieces.size(); ++p) {
    const FacePieces::Piece& piece = found.pieces[p];
    if (piece.voxels >= min_voxels) continue;
    if (piece.label == 0 && piece.touches_border) continue;  // the outside
    small.push_back(p);
  }
  if (small.empty()) return;
  std::stable_sort(small.begin(), small.end(), [&](std::uint32_t a, std::uint32_t b) {
    return found.pieces[a].voxels < found.pieces[b].voxels;
  });
  std::vector<std::uint32_t> rank(found.pieces.size(), 0);  // 1 + place in `small`, 0: kept
  for (std::size_t k = 0; k < small.size(); ++k) rank[small[k]] = static_cast<std::uint32_t>(k + 1);
  std::vector<std::size_t> first(small.size() + 1, 0);
  for (std::size_t i = 0; i < image.voxel_count(); ++i)
    if (const std::uint32_t r = rank[found.piece[i]]) ++first[r];
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<std::size_t> voxels(first.back());
  {
    std::vector<std::size_t> next(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < image.voxel_count(); ++i)
      if (const std::uint32_t r = rank[found.piece[i]]) voxels[next[r - 1]++] = i;
  }

  std::map<Label, CleanupReport::PerLabel> removed;
  for (std::size_t k = 0; k < small.size(); ++k) {
    const Label from = found.pieces[small[k]].label;
    // The label most of its face neighbors outside it have now (ties: the smaller label); past
    // the image's border is background, as the label function has it, so that an image closed
    // or not is cleaned alike.
    std::map<Label, std::size_t> votes;
    for (std::size_t v = first[k]; v < first[k + 1]; ++v) {
      for_each_face_neighbor(image, voxels[v], [&](std::size_t j) {
        if (found.piece[j] != small[k]) ++votes[image.at(j)];
      });
      votes[0] += border_faces(image.dims(), voxels[v]);
    }
    Label to = from;
    std::size_t best = 0;
    for (const auto& [l, n] : votes)
      if (l != from && n > best) best = n, to = l;
    if (to == from) continue;  // surrounded by its own label only (merged earlier): kept
    for (std::size_t v = first[k]; v < first[k + 1]; ++v) image.set(voxels[v], to);
    CleanupReport::PerLabel& r = removed[from];
    r.label = from;
    ++r.pieces;
    r.voxels += first[k + 1] - first[k];
  }
  for (const auto& [l, r] : removed) report.labels.push_back(r);
}

}  // namespace

CleanupReport clean_segmentation(LabelImage4& image, std::size_t min_voxels, unsigned threads) {
  CleanupReport report;
  if (min_voxels == 0) return report;
  remove_small_pieces(image, min_voxels, report, threads);
  report.diagonal = fill_diagonal_joins(image, threads);
  return report;
}

}  // namespace mesh4d::domain
