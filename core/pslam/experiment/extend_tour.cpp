#include "pslam/experiment/extend_tour.hpp"

#include <optional>
#include <variant>

#include "pslam/common/random.hpp"
#include "pslam/experiment/localization_tour.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/localize/mapping_handover.hpp"
#include "pslam/localize/monte_carlo_localizer.hpp"

namespace pslam {

ExtendTourResult RunExtendTour(const World& world, std::shared_ptr<const OccupancyGrid> old_map, const Pose2D& start,
                               const ExtendTourOptions& o) {
  SimulatorOptions sim_options = o.sim;
  sim_options.seed = o.seed;
  Simulator sim(world, start, sim_options);
  MclOptions mcl_options = o.mcl;
  mcl_options.seed = o.seed;
  MonteCarloLocalizer mcl(*old_map, mcl_options);
  std::mt19937_64 rng = MakeStream(o.seed, 0xe7e4d, 0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const Pose2D guess(start.x + o.initial_position_std * gauss(rng), start.y + o.initial_position_std * gauss(rng),
                     start.theta + o.initial_heading_std * gauss(rng));
  const double p2 = o.initial_position_std * o.initial_position_std;
  mcl.SetPose(guess, Eigen::Vector3d(p2, p2, o.initial_heading_std * o.initial_heading_std).asDiagonal());

  const PlanningGrid grid(world.ToGrid(), PlannerOptions{});
  std::size_t next_visit = 0;
  const auto next_route = [&](const Eigen::Vector2d& from) {
    while (next_visit < o.visit_first.size()) {
      const PlannedPath path = PlanPath(grid, from, o.visit_first[next_visit++]);
      if (path.status == PlanStatus::kFound) return path.waypoints;
    }
    return RandomRoute(grid, from, rng);
  };
  PathFollower follower;
  bool need_route = true;
  std::unique_ptr<Rbpf> filter;
  MappingHandover handover(o.handover);
  ExtendTourResult result;
  Pose2D last_truth = start;
  while (result.distance < o.distance && sim.time() < o.max_time) {
    if (need_route) {
      follower.SetPath(next_route(sim.true_pose().translation()));
      need_route = false;
    }
    const FollowerOutput drive = follower.Update(sim.true_pose());
    need_route = drive.goal_reached;
    sim.SetCommand({drive.command.linear, drive.command.angular});
    const StepResult step = sim.Step(0.1);
    if (step.collided) need_route = true;
    for (const SimulatorEvent& event : step.events) {
      const auto* scan = std::get_if<LaserScan>(&event.data);
      if (!scan) continue;
      ++result.scans;
      result.distance += (event.true_pose.translation() - last_truth.translation()).norm();
      last_truth = event.true_pose;
      if (!filter) {
        const MclUpdate update = mcl.AddScan(*scan);
        ++result.localize_scans;
        if (!handover.Ready(update)) continue;
        RbpfOptions mapping = o.mapping;
        mapping.seed = o.seed;
        mapping.prior_map = old_map;
        mapping.initial_pose = update.estimate;
        filter = std::make_unique<Rbpf>(mapping);
      }
      const RbpfStep s = filter->AddScan(*scan);
      result.final_position_error = (s.pose.translation() - event.true_pose.translation()).norm();
    }
  }
  if (filter) {
    result.localized = true;
    result.map = filter->best().map;
  } else {
    result.map = *old_map;
  }
  return result;
}

}  // namespace pslam
