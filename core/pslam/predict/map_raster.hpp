#pragma once
// A rectangular window of the occupancy grid reduced to discrete cell states: the image the
// environmental-structure predictor (P-SLAM paper, section III) works on. Plain data, no OpenCV:
// the .cpp files that need cv::Mat wrap the state vector without copying.
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

// Discrete state of a cell. The paper only distinguishes occupied, empty and unexplored; we split
// "unknown" into never observed and observed-but-undecided because the two play different roles:
// - kUnknown (grid value OccupancyGrid::kUnknown) is unexplored. Only such cells may receive a
//   prediction, and they are left out of the similarity measure.
// - kUncertain was observed, but its probability lies between the thresholds (a fringe cell seen
//   by one or two beams). It is explored for the filter, so its evidence is never predicted over,
//   and it counts as "not occupied", as an unknown cell does for eq. 3-5. For exploration it is
//   still unexplored: a hypothesis predicts it apart (Hypothesis::undecided_cells).
enum class CellState : std::uint8_t { kUnknown = 0, kUncertain = 1, kFree = 2, kOccupied = 3 };

inline bool IsExplored(CellState s) { return s != CellState::kUnknown; }

// Probability thresholds for the discrete states. The defaults sit just inside the inserter's
// single-beam updates (hit 0.70, miss 0.40 in ScanInsertOptions): one hit already marks a cell
// occupied, as a wall seen once should be a structure to match, while a cell needs two misses
// (p = 0.31) to become free.
struct CellStateThresholds {
  double occupied_above = 0.65;  // p > occupied_above: occupied
  double free_below = 0.35;      // p < free_below: free; in between: uncertain
};

// Classifies stored grid values, with the probability thresholds converted once to milli
// log-odds so that rasterising millions of cells costs one comparison each.
class CellClassifier {
 public:
  explicit CellClassifier(const CellStateThresholds& thresholds = {});
  CellState operator()(OccupancyGrid::Cell c) const {
    if (c == OccupancyGrid::kUnknown) return CellState::kUnknown;
    if (c > occupied_above_) return CellState::kOccupied;
    if (c < free_below_) return CellState::kFree;
    return CellState::kUncertain;
  }

 private:
  double occupied_above_;  // milli log-odds
  double free_below_;
};

// Cell (x, y) of the grid is element (x - origin.x(), y - origin.y()); rows run along y, so the
// raster is the map seen with y up, not flipped: angles measured in it equal world angles.
struct CellRaster {
  Eigen::Vector2i origin{0, 0};
  int width = 0;
  int height = 0;
  std::vector<CellState> cells;  // row-major, width * height

  CellRaster() = default;
  CellRaster(const Eigen::Vector2i& origin_cell, int w, int h, CellState fill = CellState::kUnknown)
      : origin(origin_cell),
        width(w),
        height(h),
        cells(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), fill) {}

  CellBox box() const {
    CellBox b;
    if (width > 0 && height > 0) b = {origin, origin + Eigen::Vector2i(width - 1, height - 1)};
    return b;
  }
  bool Contains(const Eigen::Vector2i& cell) const {
    const Eigen::Vector2i l = cell - origin;
    return l.x() >= 0 && l.y() >= 0 && l.x() < width && l.y() < height;
  }
  // State of a grid cell; kUnknown outside the window.
  CellState At(const Eigen::Vector2i& cell) const {
    return Contains(cell) ? cells[Index(cell - origin)] : CellState::kUnknown;
  }
  CellState& Local(int x, int y) { return cells[Index({x, y})]; }
  CellState Local(int x, int y) const { return cells[Index({x, y})]; }

 private:
  std::size_t Index(const Eigen::Vector2i& l) const {
    return static_cast<std::size_t>(l.y()) * static_cast<std::size_t>(width) + static_cast<std::size_t>(l.x());
  }
};

// The states of the grid cells in 'box' (inclusive); cells never observed are kUnknown. Reads
// whole tile rows at a time, so the cost is one lookup per cell plus one per 64-cell run.
CellRaster RasterizeRegion(const OccupancyGrid& grid, const CellBox& box, const CellClassifier& classify);

// 1 for the cells within 'radius' cells (Chebyshev distance) of an occupied cell of 'raster', else
// 0; row-major like raster.cells. radius 0 is the occupied mask itself.
std::vector<std::uint8_t> DilatedOccupancy(const CellRaster& raster, int radius);

}  // namespace pslam
