#include "pslam/experiment/map_similarity.hpp"

#include <algorithm>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

#include "pslam/grid/cell_key.hpp"
#include "pslam/predict/similarity.hpp"

namespace pslam {

double PredictionSimilarity(const std::vector<HypothesisCell>& predicted, const OccupancyGrid& reference,
                            const SimilarityOptions& options) {
  // ObservedSimilarity is exactly this comparison with the reference as the "later map".
  Hypothesis h;
  h.cells = predicted;
  return ObservedSimilarity(h, reference, options.states, options.tolerance_cells);
}

std::vector<HypothesisCell> TransformCells(const std::vector<HypothesisCell>& cells, const Pose2D& transform,
                                           double resolution) {
  OccupancyGrid lattice(resolution);  // cell arithmetic, and which target cells are taken
  std::vector<HypothesisCell> out;
  out.reserve(cells.size());
  for (const HypothesisCell& c : cells) {
    const Eigen::Vector2i moved = lattice.WorldToCell(transform * lattice.CellCenter(c.cell));
    if (lattice.IsKnown(moved.x(), moved.y())) continue;
    lattice.MutableAt(moved.x(), moved.y()) = 0;
    out.push_back({moved, c.occupied});
  }
  return out;
}

std::vector<HypothesisCell> MergedPredictedCells(const PSlam& slam, const std::function<Pose2D(int id)>& to_reference) {
  const OccupancyGrid& map = slam.filter().best().map;
  std::vector<HypothesisCell> cells;
  OccupancyGrid taken(map.resolution());  // a cell predicted by two hypotheses counts once, first wins
  for (const Hypothesis& h : slam.hypotheses()) {
    if (h.status == Hypothesis::Status::kRefuted) continue;  // as PSlam::MergedMap()
    std::vector<HypothesisCell> unexplored;
    for (const HypothesisCell& c : h.cells) {
      if (!map.IsKnown(c.cell.x(), c.cell.y())) unexplored.push_back(c);
    }
    // PSlam drops undecided cells the map has decided at each filter update: those left are
    // predicted still (a cell decided since the last update can be among them).
    unexplored.insert(unexplored.end(), h.undecided_cells.begin(), h.undecided_cells.end());
    if (to_reference) unexplored = TransformCells(unexplored, to_reference(h.id), map.resolution());
    for (const HypothesisCell& c : unexplored) {
      if (taken.IsKnown(c.cell.x(), c.cell.y())) continue;
      taken.MutableAt(c.cell.x(), c.cell.y()) = 0;
      cells.push_back(c);
    }
  }
  return cells;
}

namespace {

int FloorDiv(int value, int factor) { return value >= 0 ? value / factor : -((-value + factor - 1) / factor); }

Eigen::Vector2i Pooled(const Eigen::Vector2i& cell, int factor) {
  return {FloorDiv(cell.x(), factor), FloorDiv(cell.y(), factor)};
}

}  // namespace

OccupancyGrid PoolGrid(const OccupancyGrid& map, int factor) {
  OccupancyGrid pooled(map.resolution() * factor);
  const CellBox box = map.KnownBounds();
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (!map.IsKnown(x, y)) continue;
      const Eigen::Vector2i p = Pooled({x, y}, factor);
      OccupancyGrid::Cell& cell = pooled.MutableAt(p.x(), p.y());
      cell = std::max(cell, map.At(x, y));  // kUnknown is the least value: the most occupied wins
    }
  }
  return pooled;
}

std::vector<HypothesisCell> PoolCells(const std::vector<HypothesisCell>& cells, int factor) {
  std::unordered_map<std::uint64_t, std::size_t> index;  // pooled cell -> its place in 'out'
  std::vector<HypothesisCell> out;
  for (const HypothesisCell& c : cells) {
    const Eigen::Vector2i p = Pooled(c.cell, factor);
    const auto [it, added] = index.emplace(CellKey(p), out.size());
    if (added) out.push_back({p, c.occupied});
    else out[it->second].occupied = out[it->second].occupied || c.occupied;
  }
  return out;
}

double BuiltMapSimilarity(const OccupancyGrid& built, const OccupancyGrid& reference, const SimilarityOptions& options) {
  const CellBox box = built.KnownBounds();
  if (box.empty()) return 0.0;
  const CellClassifier classify(options.states);
  const CellRaster built_raster = RasterizeRegion(built, box, classify);
  CellRaster reference_raster = RasterizeRegion(reference, box, classify);
  // Only the cells the robot mapped are compared: a map is not blamed for what it never saw.
  for (std::size_t i = 0; i < built_raster.cells.size(); ++i) {
    if (!IsExplored(built_raster.cells[i])) reference_raster.cells[i] = CellState::kUnknown;
  }
  return Similarity(reference_raster, built_raster, options.tolerance_cells);
}

double MappedOrPredictedFraction(const OccupancyGrid& reference, const OccupancyGrid& built,
                                 const std::vector<HypothesisCell>& predicted) {
  std::unordered_set<std::uint64_t> predicted_cells;
  for (const HypothesisCell& c : predicted) predicted_cells.insert(CellKey(c.cell));
  const CellBox box = reference.KnownBounds();
  std::size_t free = 0, accounted = 0;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (!reference.IsKnown(x, y) || reference.Probability(x, y) >= 0.5f) continue;
      ++free;
      const Eigen::Vector2i in_built = built.WorldToCell(reference.CellCenter({x, y}));
      accounted += built.IsKnown(in_built.x(), in_built.y()) || predicted_cells.count(CellKey(x, y)) > 0;
    }
  }
  return free > 0 ? static_cast<double>(accounted) / static_cast<double>(free) : 0.0;
}

double KnownArea(const OccupancyGrid& map) {
  const CellBox box = map.KnownBounds();
  std::size_t known = 0;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) known += map.IsKnown(x, y);
  }
  return static_cast<double>(known) * map.resolution() * map.resolution();
}

}  // namespace pslam
