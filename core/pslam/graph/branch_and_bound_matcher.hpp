#pragma once
// Correlative scan matching by branch and bound (Olson 2009; Hess et al. 2016, "Real-time loop
// closure in 2D LIDAR SLAM"): the exhaustive search of a translation and rotation window for the
// pose that puts most scan points on likely-occupied cells, made fast by bounding blocks of
// 2^h x 2^h translations with grids that hold the maximum over each block.
#include <Eigen/Core>
#include <cstdint>
#include <functional>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct BranchAndBoundOptions {
  double linear_window = 3.0;     // metres each way around the initial guess
  double angular_window = 0.45;   // radians each way
  double min_score = 0.55;        // mean likelihood-field value at the points to accept a pose
  // Stop at the first pose reaching min_score instead of searching on for the best: enough to
  // tell whether any pose does (a rival), and far cheaper when one does.
  bool first_above_min_score = false;
};

struct BranchAndBoundResult {
  bool found = false;
  Pose2D pose;
  double score = 0.0;             // mean likelihood-field value at the points, in [0, 1]
};

// A likelihood field of a grid's occupied cells and its max-pooled levels, in 8 bits.
class MaxPoolStack {
 public:
  MaxPoolStack(const OccupancyGrid& grid, int depth);

  int depth() const { return static_cast<int>(levels_.size()) - 1; }
  double resolution() const { return resolution_; }
  // Max of the level-0 values over the 2^h cells square starting at (cx, cy).
  std::uint8_t At(int h, int cx, int cy) const {
    const int ix = cx - origin_.x(), iy = cy - origin_.y();
    if (ix < 0 || iy < 0 || ix >= width_ || iy >= height_) return kOutside;
    return levels_[static_cast<std::size_t>(h)][static_cast<std::size_t>(iy) * width_ + ix];
  }
  static constexpr std::uint8_t kOutside = 115;  // beyond what the grid saw: neutral, 0.45
  // Raw access for the search's inner loop: level h, row-major, width() x height(), element (0, 0)
  // at cell origin().
  const std::uint8_t* Level(int h) const { return levels_[static_cast<std::size_t>(h)].data(); }
  const Eigen::Vector2i& origin() const { return origin_; }
  int width() const { return width_; }
  int height() const { return height_; }

 private:
  double resolution_;
  Eigen::Vector2i origin_;         // cell index of element (0, 0); the arrays pad the grid by 2^depth cells
  int width_ = 0, height_ = 0;
  std::vector<std::vector<std::uint8_t>> levels_;
};

// Searches the window around `guess` (the points' pose in the grid frame). `excluded`, when set,
// rejects final poses, e.g. those near an earlier best, to find the best alternative.
BranchAndBoundResult MatchByBranchAndBound(const MaxPoolStack& stack, const std::vector<Eigen::Vector2f>& points,
                                           const Pose2D& guess, const BranchAndBoundOptions& options,
                                           const std::function<bool(const Pose2D&)>& excluded = {});

}  // namespace pslam
