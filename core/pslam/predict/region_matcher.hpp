#pragma once
// Psi of one target region S_f against many candidate alignments into one map window: the inner
// loop of the search (P-SLAM paper, eq. 1), which evaluates up to 4 x max_reference_corners
// alignments per prediction. Everything that does not depend on the alignment is done once:
// the explored cells of S_f are listed with their occupied / near-occupied flags, and the window's
// occupied cells are dilated once, so an evaluation is one affine map, one rounding and one
// byte lookup per explored cell.
//
// The result equals Similarity(target, AlignReference(...)) except that the tolerance dilation is
// applied in the reference frame before warping rather than after; for rotations by multiples of
// 90 degrees the two are identical, otherwise they differ by resampling only. The predictor ranks
// with this and reports the exact value for the alignment it keeps.
#include <cstdint>
#include <memory>
#include <vector>

#include "pslam/predict/alignment.hpp"
#include "pslam/predict/map_raster.hpp"

namespace pslam {

// The reference side of the search: a map raster's occupied and near-occupied flags. Independent
// of S_f, so a map searched by many predictions (a library map) builds it once.
struct MatchWindow {
  static constexpr std::uint8_t kOccupied = 1;
  static constexpr std::uint8_t kNearOccupied = 2;  // within the tolerance of an occupied cell

  Eigen::Vector2i origin{0, 0};
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> flags;  // row-major, kOccupied | kNearOccupied
};
MatchWindow MakeMatchWindow(const CellRaster& window, int tolerance_cells);

class RegionMatcher {
 public:
  // 'window' is the map raster the reference points index into (cells outside count as unknown);
  // 'target' is S_f.
  RegionMatcher(const CellRaster& window, const CellRaster& target, int tolerance_cells);
  RegionMatcher(std::shared_ptr<const MatchWindow> window, const CellRaster& target, int tolerance_cells);

  double Psi(const Alignment& alignment) const;
  // Psi over a fixed pseudo-random quarter of the explored cells of S_f: the same ratio estimated
  // at a quarter of the cost, for ranking many alignments before scoring the best with Psi().
  // Random rather than every other row, so that no wall direction or phase is left out.
  double CoarsePsi(const Alignment& alignment) const;
  // Explored cells of S_f: the cost of one evaluation.
  std::size_t explored_cells() const { return explored_.size(); }

 private:
  struct TargetCell {
    float x, y;           // relative to the target's origin
    std::uint8_t flags;   // kOccupied | kNearOccupied
  };
  static constexpr std::uint8_t kOccupied = MatchWindow::kOccupied;
  static constexpr std::uint8_t kNearOccupied = MatchWindow::kNearOccupied;

  double PsiOver(const std::vector<TargetCell>& cells, std::int64_t target_occupied, const Alignment& alignment) const;

  std::shared_ptr<const MatchWindow> window_;
  Eigen::Vector2i target_origin_;
  std::vector<TargetCell> explored_;
  std::int64_t target_occupied_ = 0;
  std::vector<TargetCell> sampled_;  // the quarter CoarsePsi uses
  std::int64_t sampled_occupied_ = 0;
};

}  // namespace pslam
