// Loop closure in a featureless corridor searched through a narrow window: the match may sit
// anywhere along the corridor, and a window narrower than the rival distance leaves no room to
// see that. Rivals are looked for in a wider window (LoopClosureOptions::min_rival_window).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pslam/graph/loop_closure.hpp"
#include "pslam/sensor/scan_points.hpp"
#include "pslam/sim/laser_model.hpp"
#include "pslam/sim/world_painter.hpp"

namespace pslam {
namespace {

constexpr double kDrift = 0.25;  // metres along the corridor the return leg's estimate is off

struct Outcome {
  LoopClosureStats stats;
  int wrong = 0;  // closure edges that disagree with the truth by more than 0.15 m
};

// Down a 40 m corridor and back, the ends always beyond the 8 m laser; on the way back the
// estimate is kDrift ahead of the truth along the corridor, inside the 0.3 m search window.
Outcome DriveBack(double min_rival_window) {
  const World world = MakeWalledRoom(40.0, 2.2, 0.2, 0.05);
  std::vector<Pose2D> truth, estimate;
  for (double x = 10.0; x <= 30.0; x += 0.5) truth.emplace_back(x, 1.1, 0.0);
  const std::size_t outbound = truth.size();
  for (double x = 30.0; x >= 10.0; x -= 0.5) truth.emplace_back(x, 1.1, M_PI);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    estimate.push_back(truth[k]);
    if (k >= outbound) estimate.back().x += kDrift;
  }

  LoopClosureOptions options;
  options.enabled = true;
  options.nodes_per_submap = 8;
  options.base_window = 0.3;
  options.window_per_metre = 0.0;
  options.max_window = 0.3;
  options.min_rival_window = min_rival_window;
  LoopCloser closer(options, ScanInsertOptions{}, 0.05);
  std::mt19937_64 rng(5);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    closer.AddNode(static_cast<int>(k), estimate[k], ToScanPoints(SimulateScan(world, truth[k], LaserOptions{}, rng), {}));
  }
  closer.Flush();

  Outcome out{closer.stats()};
  for (const PoseGraphEdge& e : closer.graph().edges()) {
    if (e.huber_scale <= 0.0) continue;
    const Pose2D t = Between(truth[static_cast<std::size_t>(e.from)], truth[static_cast<std::size_t>(e.to)]);
    if (std::hypot(e.measurement.x - t.x, e.measurement.y - t.y) > 0.15) ++out.wrong;
  }
  return out;
}

TEST(LoopCloserCorridorTest, NarrowWindowAloneAcceptsASlideAlongTheCorridor) {
  // Rivals looked for only inside the 0.3 m window: none fits 0.6 m away, so the flat match passes.
  const Outcome out = DriveBack(0.0);
  EXPECT_GT(out.stats.closures, 0);
  EXPECT_GT(out.wrong, 0) << "the closures keep the drift they should have removed";
}

TEST(LoopCloserCorridorTest, RivalsAlongTheCorridorRefuseTheClosure) {
  const Outcome out = DriveBack(1.5);
  EXPECT_EQ(out.stats.closures, 0);
  EXPECT_EQ(out.wrong, 0);
  EXPECT_GT(out.stats.ambiguous, 0) << "the corridor was searched and found to repeat itself";
}

}  // namespace
}  // namespace pslam
