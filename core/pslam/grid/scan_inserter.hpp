#pragma once
// The inverse sensor model: cells along each beam become more likely free, the endpoint cell more
// likely occupied, in log-odds with clamping so that the map stays able to change.
#include "pslam/common/pose2d.hpp"
#include "pslam/grid/occupancy_grid.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

struct ScanInsertOptions {
  double hit_probability = 0.7;
  double miss_probability = 0.4;
  double min_probability = 0.12;   // clamping: how sure a cell may become of being free ...
  double max_probability = 0.97;   // ... or occupied
  // A beam that meets its surface at a shallow angle stops clearing where it would enter the
  // surface's row of cells (scan_inserter.cpp, GrazingStop; measured in docs/loop-closure.md).
  bool grazing_stop = true;
};

class ScanInserter {
 public:
  explicit ScanInserter(const ScanInsertOptions& options = {});
  // Misses first, then hits, so that a beam grazing a wall does not erase another beam's hit.
  // Every cell the scan observes is also forgotten in `forget` when given: that is how predicted
  // cells give way to observed ones (the hypothesis validation V of the paper's eq. 20).
  void Insert(const ScanPoints& points, const Pose2D& robot_pose, OccupancyGrid& grid,
              OccupancyGrid* forget = nullptr) const;

 private:
  int hit_, miss_, lo_, hi_;  // milli log-odds
  bool grazing_stop_;
};

}  // namespace pslam
