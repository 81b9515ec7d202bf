#include "pslam/experiment/prediction_latency.hpp"

#include <time.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "pslam/explore/frontier.hpp"
#include "pslam/predict/structure_predictor.hpp"

namespace pslam {
namespace {

double ProcessCpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

}  // namespace

OccupancyGrid CropMap(const OccupancyGrid& map, const CellBox& box) {
  OccupancyGrid crop(map.resolution());
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const OccupancyGrid::Cell v = map.At(x, y);
      if (v != OccupancyGrid::kUnknown) crop.MutableAt(x, y) = v;
    }
  }
  return crop;
}

std::vector<Eigen::Vector2i> FrontierTargets(const OccupancyGrid& map, int count) {
  const std::vector<FrontierCluster> clusters = FindFrontierClusters(map);
  std::vector<Eigen::Vector2i> targets;
  if (clusters.empty() || count <= 0) return targets;
  const auto nearest_centroid = [&map](const FrontierCluster& cluster) {
    std::size_t best = 0;
    double nearest = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < cluster.cells.size(); ++i) {
      const double d = (map.CellCenter(cluster.cells[i]) - cluster.centroid).squaredNorm();
      if (d < nearest) {
        nearest = d;
        best = i;
      }
    }
    return best;
  };
  const auto wanted = static_cast<std::size_t>(count);
  if (clusters.size() >= wanted) {
    for (std::size_t k = 0; k < wanted; ++k) {
      const FrontierCluster& cluster = clusters[k * clusters.size() / wanted];
      targets.push_back(cluster.cells[nearest_centroid(cluster)]);
    }
    return targets;
  }
  // Round j takes, from every cluster, the cell j/per_cluster of the way along it from its
  // centroid cell (cells in row-major order, wrapping around).
  const std::size_t per_cluster = (wanted + clusters.size() - 1) / clusters.size();
  for (std::size_t j = 0; j < per_cluster && targets.size() < wanted; ++j) {
    for (const FrontierCluster& cluster : clusters) {
      if (targets.size() == wanted) break;
      const std::size_t n = cluster.cells.size();
      targets.push_back(cluster.cells[(nearest_centroid(cluster) + j * n / per_cluster) % n]);
    }
  }
  return targets;
}

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const double position = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
  const auto lower = static_cast<std::size_t>(std::floor(position));
  const std::size_t upper = std::min(lower + 1, values.size() - 1);
  const double t = position - static_cast<double>(lower);
  return values[lower] + t * (values[upper] - values[lower]);
}

LatencyStats MeasurePredictionLatency(const OccupancyGrid& map, const std::vector<Eigen::Vector2i>& targets,
                                      const PredictorOptions& options) {
  StructurePredictor predictor(options);
  LatencyStats stats;
  std::vector<double> searched_cpu_ms;
  double feature_ms = 0.0, total_ms = 0.0;
  for (const Eigen::Vector2i& target : targets) {
    const double cpu_before = ProcessCpuMs();
    const bool hypothesis = predictor.Predict(map, target, 0.0).has_value();
    const double cpu = ProcessCpuMs() - cpu_before;
    const PredictionReport& report = predictor.last_report();
    stats.hypotheses += hypothesis;
    ++stats.predictions;
    stats.ms.push_back(report.total_ms);
    stats.cpu_ms.push_back(cpu);
    stats.best_psi.push_back(report.best_psi);
    feature_ms += report.features_ms;
    total_ms += report.total_ms;
    if (report.alignments > 0) searched_cpu_ms.push_back(cpu);
  }
  const auto max = [](const std::vector<double>& v) { return v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()); };
  stats.searched = static_cast<int>(searched_cpu_ms.size());
  stats.feature_share = total_ms > 0.0 ? feature_ms / total_ms : 0.0;
  stats.median_ms = Quantile(stats.ms, 0.5);
  stats.p95_ms = Quantile(stats.ms, 0.95);
  stats.max_ms = max(stats.ms);
  stats.cpu_median_ms = Quantile(stats.cpu_ms, 0.5);
  stats.cpu_p95_ms = Quantile(stats.cpu_ms, 0.95);
  stats.cpu_max_ms = max(stats.cpu_ms);
  stats.searched_cpu_median_ms = Quantile(searched_cpu_ms, 0.5);
  stats.searched_cpu_p95_ms = Quantile(searched_cpu_ms, 0.95);
  return stats;
}

}  // namespace pslam
