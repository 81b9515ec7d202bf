#include "pslam/predict/structure_predictor.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "pslam/predict/alignment.hpp"
#include "pslam/predict/features.hpp"
#include "pslam/predict/map_raster.hpp"
#include "pslam/predict/region_matcher.hpp"
#include "pslam/predict/similarity.hpp"

namespace pslam {
namespace {

using Clock = std::chrono::steady_clock;

double MsSince(Clock::time_point start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// d_s = ceil(d / resolution) of eq. 5; the epsilon keeps 10 m / 0.05 m at 200, not 201.
int CellsFor(double metres, double resolution) {
  return std::max(1, static_cast<int>(std::ceil(metres / resolution - 1e-9)));
}

// The 'size' x 'size' square of cells with 'centre' in its middle (for an even size, the centre
// is the first cell right of and above the middle).
CellBox SquareAround(const Eigen::Vector2i& centre, int size) {
  CellBox box;
  box.min = centre - Eigen::Vector2i(size / 2, size / 2);
  box.max = box.min + Eigen::Vector2i(size - 1, size - 1);
  return box;
}

CellBox Intersection(const CellBox& a, const CellBox& b) {
  CellBox box;
  box.min = a.min.cwiseMax(b.min);
  box.max = a.max.cwiseMin(b.max);
  return box;
}

// Cells covered by the grid's tiles: O(1), unlike KnownBounds(), which reads every cell.
CellBox GridExtent(const OccupancyGrid& grid) {
  CellBox box;
  if (grid.tiles_wide() == 0 || grid.tiles_high() == 0) return box;
  box.min = grid.tile_origin() * OccupancyGrid::kTileSize;
  box.max = (grid.tile_origin() + Eigen::Vector2i(grid.tiles_wide(), grid.tiles_high())) * OccupancyGrid::kTileSize -
            Eigen::Vector2i(1, 1);
  return box;
}

// The four theta = phi_i(P1) - phi_j(P2) of eq. 2, without near duplicates (a one-armed corner's
// perpendicular can repeat an angle of the other corner's pair).
std::vector<double> CandidateAngles(const Corner& target, const Corner& reference) {
  std::vector<double> angles;
  for (const double p1 : {target.phi1, target.phi2}) {
    for (const double p2 : {reference.phi1, reference.phi2}) {
      const double theta = NormalizeAngle(p1 - p2);
      const bool seen = std::any_of(angles.begin(), angles.end(), [&](double a) {
        return std::abs(NormalizeAngle(a - theta)) < 0.5 * std::numbers::pi / 180.0;
      });
      if (!seen) angles.push_back(theta);
    }
  }
  return angles;
}

struct Candidate {
  Alignment alignment;
  double psi = 0.0;
  std::size_t source = 0;  // index into the sources: 0 the map being built, then the library maps
};

// A map searched for references: the map being built, or a library map (features cached there).
struct Source {
  const OccupancyGrid* map = nullptr;
  std::string id;  // empty for the map being built
  RegionMatcher matcher;
};

// Local search around 'start' (predictor_options.hpp, refined_candidates): theta in +-2 steps of
// 'angle_step', P1 in +-1 cell, kRefineEvaluations alignments. Keeps 'start' unless a neighbour
// is strictly better.
constexpr int kRefineEvaluations = 5 * 9 - 1;
Candidate Refine(const RegionMatcher& matcher, const Candidate& start, double angle_step) {
  Candidate best = start;
  for (int k = -2; k <= 2; ++k) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (k == 0 && dx == 0 && dy == 0) continue;
        Alignment a = start.alignment;
        a.theta = start.alignment.theta + k * angle_step;
        a.target_point += Eigen::Vector2d(dx, dy);
        const double psi = matcher.Psi(a);
        if (psi > best.psi) best = {a, psi, start.source};
      }
    }
  }
  return best;
}

// The aligned reference on the cells 'target' has not explored, unknown elsewhere: what the
// alignment predicts.
CellRaster PredictedPart(const CellRaster& target, const CellRaster& aligned) {
  CellRaster predicted(target.origin, target.width, target.height);
  for (std::size_t i = 0; i < target.cells.size(); ++i) {
    if (target.cells[i] == CellState::kUnknown) predicted.cells[i] = aligned.cells[i];
  }
  return predicted;
}

// Whether 'other' predicts the cells of 'predicted' alike (see PredictorOptions::ambiguity_*):
// Psi over the cells 'predicted' holds, or agreement when neither side has a wall there. A wall
// the other alignment does not know counts against: a prediction only one of two equally good
// references makes is not corroborated. (Counting only cells both know was measured too: on the
// office, seeds 1-3, 57.6 % of hypotheses reached Psi 0.4 against the final map, against 66.1 %.)
bool Agrees(const CellRaster& predicted, const CellRaster& other, const PredictorOptions& o) {
  const OverlapCounts overlap = CountOverlap(predicted, other, o.tolerance_cells);
  if (overlap.target_occupied + overlap.aligned_occupied == 0) return true;
  return overlap.Psi() >= o.ambiguity_agreement;
}

}  // namespace

StructurePredictor::StructurePredictor(const PredictorOptions& options, MapLibrary library)
    : options_(options), classify_(options.states), library_(std::move(library)) {
  if (const auto error = ValidatePredictorOptions(options)) throw std::invalid_argument(*error);
  if (static_cast<int>(library_.size()) > options_.max_library_maps) library_.resize(options_.max_library_maps);
  for (const auto& entry : library_) {
    if (!entry) throw std::invalid_argument("library map: null");
  }
}

std::optional<Hypothesis> StructurePredictor::Predict(const OccupancyGrid& map, const Eigen::Vector2i& target,
                                                      double time, std::stop_token stop) {
  const Clock::time_point start = Clock::now();
  report_ = {};
  std::optional<Hypothesis> hypothesis = Run(map, target, time, stop);
  report_.total_ms = MsSince(start);
  ++stats_.predictions;
  stats_.last_ms = report_.total_ms;
  stats_.max_ms = std::max(stats_.max_ms, report_.total_ms);
  stats_.total_ms += report_.total_ms;
  switch (report_.outcome) {
    case PredictionReport::Outcome::kHypothesis: ++stats_.hypotheses; break;
    case PredictionReport::Outcome::kNoControlPoint: ++stats_.no_control_point; break;
    case PredictionReport::Outcome::kTooLittleStructure: ++stats_.too_little_structure; break;
    case PredictionReport::Outcome::kNoReferenceCorner: ++stats_.no_reference_corner; break;
    case PredictionReport::Outcome::kBelowThreshold: ++stats_.below_threshold; break;
    case PredictionReport::Outcome::kAmbiguous: ++stats_.ambiguous; break;
    case PredictionReport::Outcome::kNothingToPredict: ++stats_.nothing_to_predict; break;
    case PredictionReport::Outcome::kCancelled: ++stats_.cancelled; break;
  }
  return hypothesis;
}

std::optional<Hypothesis> StructurePredictor::Run(const OccupancyGrid& map, const Eigen::Vector2i& target,
                                                  double time, const std::stop_token& stop) {
  using Outcome = PredictionReport::Outcome;
  const Clock::time_point start = Clock::now();
  const double resolution = map.resolution();
  const int region_cells = CellsFor(options_.region_size_m, resolution);
  const CellBox target_box = SquareAround(target, region_cells);

  // 1-2. Features on the window that holds every usable reference corner and its whole region.
  const double margin_m =
      options_.search_radius_m + options_.region_size_m / std::numbers::sqrt2 + options_.control_point_range_m;
  const CellBox window_box =
      Intersection(SquareAround(target, 2 * CellsFor(margin_m, resolution) + 1), GridExtent(map));
  if (window_box.empty()) {
    report_.outcome = Outcome::kNoControlPoint;
    return std::nullopt;
  }
  const CellRaster window = RasterizeRegion(map, window_box, classify_);
  const MapFeatures features = ExtractFeatures(window, resolution, options_.features);
  report_.corners = static_cast<int>(features.corners.size());
  report_.features_ms = MsSince(start);
  const Clock::time_point search_start = Clock::now();
  if (stop.stop_requested()) {
    report_.outcome = Outcome::kCancelled;
    return std::nullopt;
  }

  // 3. Control point P1: the corner nearest to f within range (the strongest on a tie).
  const Eigen::Vector2d f = target.cast<double>();
  const Corner* control = nullptr;
  double control_distance = options_.control_point_range_m / resolution;
  for (const Corner& c : features.corners) {
    const double distance = (c.position - f).norm();
    if (distance <= control_distance && (!control || distance < control_distance)) {
      control = &c;
      control_distance = distance;
    }
  }
  if (!control) {
    report_.outcome = Outcome::kNoControlPoint;
    return std::nullopt;
  }

  const CellRaster target_raster = RasterizeRegion(map, target_box, classify_);
  const auto structure = std::count(target_raster.cells.begin(), target_raster.cells.end(), CellState::kOccupied);
  if (static_cast<double>(structure) * resolution < options_.min_structure_m) {
    report_.outcome = Outcome::kTooLittleStructure;
    return std::nullopt;
  }

  // 4. Reference corners: strongest first (the corner list is sorted), outside the target
  // neighbourhood, inside the search radius, at most max_reference_corners of them; then as many
  // of each library map of the same resolution, strongest first (another frame: no radius).
  std::vector<Source> sources;
  sources.push_back({&map, {}, RegionMatcher(window, target_raster, options_.tolerance_cells)});
  std::vector<std::pair<const Corner*, std::size_t>> references;
  const double exclusion = options_.min_reference_distance_m / resolution;
  const double reach = options_.search_radius_m / resolution;
  for (const Corner& c : features.corners) {
    if (static_cast<int>(references.size()) >= options_.max_reference_corners) break;
    if (&c == control || (c.position - control->position).norm() < exclusion || (c.position - f).norm() > reach) {
      continue;
    }
    references.push_back({&c, 0});
  }
  for (const auto& entry : library_) {
    if (std::abs(entry->map.resolution() - resolution) > 1e-9 * resolution) continue;
    sources.push_back({&entry->map, entry->id, RegionMatcher(entry->window, target_raster, options_.tolerance_cells)});
    const std::size_t n = std::min(entry->corners.size(), static_cast<std::size_t>(options_.max_reference_corners));
    for (std::size_t i = 0; i < n; ++i) references.push_back({&entry->corners[i], sources.size() - 1});
  }
  report_.reference_corners = static_cast<int>(references.size());
  if (references.empty()) {
    report_.outcome = Outcome::kNoReferenceCorner;
    return std::nullopt;
  }

  std::vector<Candidate> candidates;
  candidates.reserve(4 * references.size());
  for (const auto& [reference, source] : references) {
    const RegionMatcher& matcher = sources[source].matcher;
    if (stop.stop_requested()) {
      report_.outcome = Outcome::kCancelled;
      return std::nullopt;
    }
    for (const double theta : CandidateAngles(*control, *reference)) {
      const Alignment alignment{control->position, reference->position, theta};
      const bool coarse = options_.coarse_rescored > 0;
      candidates.push_back({alignment, coarse ? matcher.CoarsePsi(alignment) : matcher.Psi(alignment), source});
    }
  }
  report_.alignments = static_cast<int>(candidates.size());
  const auto better = [](const Candidate& a, const Candidate& b) { return a.psi > b.psi; };
  std::stable_sort(candidates.begin(), candidates.end(), better);
  if (options_.coarse_rescored > 0) {
    // Coarse to fine (predictor_options.hpp): the best coarse scores, scored on every cell.
    candidates.resize(std::min(candidates.size(), static_cast<std::size_t>(options_.coarse_rescored)));
    for (Candidate& c : candidates) c.psi = sources[c.source].matcher.Psi(c.alignment);
    report_.alignments += static_cast<int>(candidates.size());
    std::stable_sort(candidates.begin(), candidates.end(), better);
  }

  // Refine the best few, then score them exactly (similarity.hpp) and keep the best.
  const std::size_t kept =
      std::min(candidates.size(), static_cast<std::size_t>(std::max(1, options_.refined_candidates)));
  const double angle_step = 2.0 / region_cells;  // moves the edge of S_f by about one cell
  Candidate best;
  std::optional<CellRaster> best_aligned;
  for (std::size_t i = 0; i < kept; ++i) {
    Candidate c = candidates[i];
    if (options_.refined_candidates > 0) {
      c = Refine(sources[c.source].matcher, c, angle_step);
      report_.alignments += kRefineEvaluations;
    }
    CellRaster aligned = AlignReference(*sources[c.source].map, target_box, c.alignment, classify_);
    c.psi = Similarity(target_raster, aligned, options_.tolerance_cells);
    if (!best_aligned || c.psi > best.psi) {
      best = c;
      best_aligned = std::move(aligned);
    }
  }
  report_.best_psi = best.psi;
  if (best.psi < options_.similarity_threshold) {
    report_.outcome = Outcome::kBelowThreshold;
    report_.search_ms = MsSince(search_start);
    return std::nullopt;
  }

  // An equally good alignment that predicts something else: the match is ambiguous.
  if (options_.ambiguity_margin > 0.0) {
    const CellRaster predicted = PredictedPart(target_raster, *best_aligned);
    for (const Candidate& other : candidates) {
      if (other.psi < best.psi - options_.ambiguity_margin) break;  // sorted by Psi
      if (stop.stop_requested()) {
        report_.outcome = Outcome::kCancelled;
        return std::nullopt;
      }
      const CellRaster aligned = AlignReference(*sources[other.source].map, target_box, other.alignment, classify_);
      if (!Agrees(predicted, aligned, options_)) {
        report_.outcome = Outcome::kAmbiguous;
        report_.search_ms = MsSince(search_start);
        return std::nullopt;
      }
    }
  }

  // 5. The hypothesis: reference states on the never-observed cells of S_f only.
  Hypothesis h;
  for (int y = 0; y < target_raster.height; ++y) {
    for (int x = 0; x < target_raster.width; ++x) {
      const CellState target_state = target_raster.Local(x, y);
      if (target_state != CellState::kUnknown && target_state != CellState::kUncertain) continue;
      const CellState predicted = best_aligned->Local(x, y);
      if (predicted != CellState::kOccupied && predicted != CellState::kFree) continue;
      const HypothesisCell cell{target_box.min + Eigen::Vector2i(x, y), predicted == CellState::kOccupied};
      (target_state == CellState::kUnknown ? h.cells : h.undecided_cells).push_back(cell);
    }
  }
  report_.search_ms = MsSince(search_start);
  if (h.cells.empty()) {
    report_.outcome = Outcome::kNothingToPredict;
    return std::nullopt;
  }
  const Alignment& a = best.alignment;
  h.id = next_id_++;
  h.time = time;
  h.target_cell = target;
  h.reference_map = sources[best.source].id;
  h.reference_cell = NearestCell(a.ToReference(f));
  h.theta = NormalizeAngle(a.theta);
  h.target_control_point = (a.target_point + Eigen::Vector2d(0.5, 0.5)) * resolution;
  h.reference_control_point = (a.reference_point + Eigen::Vector2d(0.5, 0.5)) * resolution;
  h.translation = h.target_control_point - h.reference_control_point;
  h.psi = best.psi;
  h.area_m2 = static_cast<double>(h.cells.size()) * resolution * resolution;
  report_.outcome = Outcome::kHypothesis;
  return h;
}

}  // namespace pslam
