#include "pslam/experiment/map_alignment.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "pslam/experiment/map_similarity.hpp"
#include "pslam/graph/branch_and_bound_matcher.hpp"
#include "pslam/grid/cell_key.hpp"
#include "pslam/grid/grid_transform.hpp"
#include "pslam/matching/scan_matcher.hpp"

namespace pslam {

MapAlignment AlignMap(const OccupancyGrid& built, const OccupancyGrid& reference, const MapAlignmentOptions& options) {
  if (std::abs(built.resolution() - reference.resolution()) > 1e-9 * reference.resolution()) {
    throw std::invalid_argument("map resolutions differ: reference " + std::to_string(reference.resolution()) +
                                " m, built " + std::to_string(built.resolution()) + " m");
  }
  const SimilarityOptions similarity{.states = options.states};
  MapAlignment out;
  out.psi = out.laid_psi = BuiltMapSimilarity(built, reference, similarity);
  const CellBox box = built.KnownBounds();
  if (box.empty()) return out;
  // One occupied cell per cloud_spacing square, relative to the map's centre, so that the search
  // turns the map about its middle rather than about the frame's origin.
  const CellClassifier classify(options.states);
  const double resolution = built.resolution();
  const Eigen::Vector2d centre = 0.5 * (built.CellCenter(box.min) + built.CellCenter(box.max));
  const int stride = std::max(1, static_cast<int>(std::lround(options.cloud_spacing / resolution)));
  // Floor division, so that each block of stride x stride cells keeps one cell on both sides of 0.
  const auto block = [stride](int v) { return v >= 0 ? v / stride : (v - stride + 1) / stride; };
  std::unordered_set<std::uint64_t> taken;
  std::vector<Eigen::Vector2f> cloud;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (classify(built.At(x, y)) != CellState::kOccupied) continue;
      if (!taken.insert(CellKey(block(x), block(y))).second) continue;
      cloud.push_back((built.CellCenter({x, y}) - centre).cast<float>());
    }
  }
  if (cloud.empty()) return out;
  const int depth = std::max(1, static_cast<int>(std::ceil(std::log2(options.linear_window / resolution + 1.0))));
  const MaxPoolStack stack(reference, depth);
  const BranchAndBoundOptions search{.linear_window = options.linear_window,
                                     .angular_window = options.angular_window,
                                     .min_score = 0.0};
  const BranchAndBoundResult found = MatchByBranchAndBound(stack, cloud, Pose2D{centre.x(), centre.y(), 0.0}, search);
  if (!found.found) return out;
  // The search steps the angle by about a cell at the cloud's far end; the finest level of the
  // scan matcher goes on between those steps.
  std::vector<Pose2D> poses{found.pose};
  const ScanMatchResult refined = MatchScan(reference, cloud, found.pose, ScanMatchOptions{.coarsest_level = 0});
  if (refined.converged) poses.push_back(refined.pose);
  for (const Pose2D& at : poses) {
    const Pose2D move = at * Pose2D{-centre.x(), -centre.y(), 0.0};
    const double psi = BuiltMapSimilarity(TransformGrid(built, move), reference, similarity);
    if (psi <= out.laid_psi) continue;
    out.move = move;
    out.laid_psi = psi;
    out.centre_shift = std::hypot(at.x - centre.x(), at.y - centre.y());
  }
  return out;
}

}  // namespace pslam
