#pragma once
// Frontiers (Yamauchi, "A frontier-based approach for autonomous exploration", 1997): free cells
// that touch unknown space, grouped into clusters; driving to a cluster reveals what lies beyond.
#include <Eigen/Core>
#include <vector>

#include "pslam/explore/cell_class.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

struct FrontierOptions {
  CellClassOptions classes;
  // Clusters with fewer cells are dropped: single cells at scan edges and between beams are noise,
  // not openings. 8 cells at 5 cm = 40 cm, narrower than anything the robot fits through.
  int min_cluster_cells = 8;
};

struct FrontierCluster {
  std::vector<Eigen::Vector2i> cells;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  // world coordinates, mean of cell centres
  std::size_t size() const { return cells.size(); }
};

// Free cells with at least one unknown 4-neighbour, in row-major order over the known bounds.
std::vector<Eigen::Vector2i> FindFrontierCells(const OccupancyGrid& grid, const FrontierOptions& options = {});

// 8-connected components of the frontier cells (a diagonal frontier is one opening), each with at
// least min_cluster_cells cells, largest first (ties in row-major order of their first cell).
std::vector<FrontierCluster> FindFrontierClusters(const OccupancyGrid& grid, const FrontierOptions& options = {});

}  // namespace pslam
