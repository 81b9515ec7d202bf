#include "pslam/experiment/localization_tour.hpp"

#include <time.h>

#include <cmath>
#include <numbers>
#include <stdexcept>

#include "pslam/common/random.hpp"
#include "pslam/explore/look_around.hpp"
#include "pslam/explore/path_follower.hpp"
#include "pslam/explore/path_planner.hpp"
#include "pslam/explore/planning_grid.hpp"
#include "pslam/filter/rbpf.hpp"
#include "pslam/localize/monte_carlo_localizer.hpp"

namespace pslam {
namespace {

double CpuSeconds(clockid_t clock) {
  timespec t{};
  clock_gettime(clock, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

std::vector<Eigen::Vector2d> RandomRoute(const PlanningGrid& grid, const Eigen::Vector2d& from, std::mt19937_64& rng) {
  std::uniform_int_distribution<std::size_t> pick(0, grid.size() - 1);
  for (int attempt = 0; attempt < 200; ++attempt) {
    const Eigen::Vector2i cell = grid.CellAt(pick(rng));
    if (!grid.IsTraversable(cell)) continue;
    const PlannedPath path = PlanPath(grid, from, grid.CellCenter(cell));
    if (path.status == PlanStatus::kFound && path.length > 3.0) return path.waypoints;
  }
  return {};
}

LocalizationTourResult RunLocalizationTour(const World& world, const OccupancyGrid& map, const Pose2D& start,
                                           const LocalizationTourOptions& o) {
  SimulatorOptions sim_options = o.sim;
  sim_options.seed = o.seed;
  Simulator sim(world, start, sim_options);
  MclOptions mcl_options = o.mcl;
  mcl_options.seed = o.seed;
  MonteCarloLocalizer mcl(map, mcl_options);
  std::mt19937_64 rng = MakeStream(o.seed, 0x7011, 0);
  if (!o.global) {
    std::normal_distribution<double> gauss(0.0, 1.0);
    const Pose2D guess(start.x + o.initial_position_std * gauss(rng), start.y + o.initial_position_std * gauss(rng),
                       start.theta + o.initial_heading_std * gauss(rng));
    const double p2 = o.initial_position_std * o.initial_position_std;
    mcl.SetPose(guess, Eigen::Vector3d(p2, p2, o.initial_heading_std * o.initial_heading_std).asDiagonal());
  } else {
    mcl.StartGlobal();
  }

  const PlanningGrid grid(world.ToGrid(), PlannerOptions{});
  PathFollower follower;
  bool need_route = true, kidnapped = false;
  bool searching = false;
  LookAround look_around(o.look_around_rate);
  std::vector<LaserScan> scans;
  LocalizationTourResult result;
  Pose2D last_truth = start;
  double cpu = 0.0;
  while (result.distance < o.distance && sim.time() < o.max_time) {
    if (o.kidnap_after > 0.0 && !kidnapped && result.distance >= o.kidnap_after) {
      sim.Teleport(o.kidnap_pose);
      last_truth = o.kidnap_pose;
      kidnapped = need_route = true;
    }
    const double turn_rate = look_around.Update(sim.true_pose().theta);
    if (look_around.active()) {
      sim.SetCommand({0.0, turn_rate});
    } else {
      if (need_route) {
        follower.SetPath(RandomRoute(grid, sim.true_pose().translation(), rng));
        need_route = false;
      }
      const FollowerOutput drive = follower.Update(sim.true_pose());
      need_route = drive.goal_reached;
      sim.SetCommand({drive.command.linear, drive.command.angular});
    }
    const StepResult step = sim.Step(0.1);
    if (step.collided) need_route = true;
    for (const SimulatorEvent& event : step.events) {
      const auto* scan = std::get_if<LaserScan>(&event.data);
      if (!scan) continue;
      result.distance += (event.true_pose.translation() - last_truth.translation()).norm();
      last_truth = event.true_pose;
      const double before = CpuSeconds(CLOCK_THREAD_CPUTIME_ID);
      const MclUpdate update = mcl.AddScan(*scan);
      cpu += CpuSeconds(CLOCK_THREAD_CPUTIME_ID) - before;
      if (o.look_around && update.searching && !searching) look_around.Start(2.0 * std::numbers::pi, sim.true_pose().theta);
      searching = update.searching;
      result.samples.push_back({event.time, result.distance, event.true_pose, update.estimate, update.localized,
                                update.particles});
      if (o.measure_mapping) scans.push_back(*scan);
    }
  }
  result.scans = mcl.stats().scans;
  result.updates = mcl.stats().updates;
  result.min_particles = mcl.stats().min_particles_seen;
  result.max_particles = mcl.stats().max_particles_seen;
  result.localizer_cpu_ms_per_scan = result.scans ? 1e3 * cpu / result.scans : 0.0;
  if (o.measure_mapping && !scans.empty()) {
    RbpfOptions mapping = o.mapping;
    mapping.initial_pose = start;
    Rbpf filter(mapping);
    const double before = CpuSeconds(CLOCK_PROCESS_CPUTIME_ID);  // the filter's worker threads count too
    for (const LaserScan& scan : scans) filter.AddScan(scan);
    result.mapping_cpu_ms_per_scan = 1e3 * (CpuSeconds(CLOCK_PROCESS_CPUTIME_ID) - before) / static_cast<double>(scans.size());
  }
  return result;
}

TrackingError MeasureTracking(const std::vector<LocalizationSample>& samples, double from_distance) {
  TrackingError e;
  for (const LocalizationSample& s : samples) {
    if (s.distance < from_distance) continue;
    const double d = (s.estimate.translation() - s.truth.translation()).norm();
    e.mean_position += d;
    e.mean_heading += std::abs(NormalizeAngle(s.estimate.theta - s.truth.theta));
    e.max_position = std::max(e.max_position, d);
    ++e.samples;
  }
  if (e.samples) {
    e.mean_position /= e.samples;
    e.mean_heading /= e.samples;
  }
  return e;
}

std::optional<double> ConvergenceDistance(const std::vector<LocalizationSample>& samples, double threshold,
                                          double from_distance) {
  std::optional<double> since;
  for (const LocalizationSample& s : samples) {
    if (s.distance < from_distance) continue;
    const bool close = (s.estimate.translation() - s.truth.translation()).norm() < threshold;
    if (!close) since.reset();
    else if (!since) since = s.distance - from_distance;
  }
  return since;
}

}  // namespace pslam
