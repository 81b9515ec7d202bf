// `pslam experiment extend`: lifelong mapping. A first session explores a world and maps it; a few
// walls move; a second session extends the first map on the changed world. The new version's Psi
// against the changed world is set against the first version's Psi against the original, with the
// prior's confidence capped (what extend mode does) and not (what shows whether old walls stay).
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "experiment_common.hpp"
#include "pslam/experiment/extend_tour.hpp"
#include "pslam/experiment/map_similarity.hpp"
#include "pslam/sim/wall_moves.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam experiment extend [--world FILE.yaml] [--changed FILE.yaml | --moves N --move-seed S]\n"
    "                               [--runs N] [--distance M] [--write-changed PREFIX] [--json OUT]\n"
    "                               [exploration flags]\n"
    "  Explores the world (default core/worlds/office.yaml) and maps it: the first version. Then the\n"
    "  world changes: --changed loads the changed world, else N (3) pieces of interior wall or\n"
    "  free-standing obstacles move 1 m sideways (deterministic for --move-seed, 1; --write-changed\n"
    "  saves PREFIX-SEED). They move only where the first map shows them. A\n"
    "  second session localizes on the first version in the changed world, then extends it while\n"
    "  touring both sides of each change and M (120) m of random goals, with the prior's confidence\n"
    "  capped and again without the cap. Prints Psi (occupied cells, one-cell tolerance) of each\n"
    "  map against its world, for seeds S, S+1, ... (--runs N, default 1), and of the first map's\n"
    "  walls where the world is free now, the share each new map still has as wall.\n";

// Of the cells the first map has as wall where the world is free now (walls that moved away),
// the share 'map' still has as wall; NaN when there are none. The maps are taken in the world
// frame, which holds where the first map did not slip.
double StaleWalls(const OccupancyGrid& first, const OccupancyGrid& map, const World& original, const World& changed) {
  int stale = 0, n = 0;
  const CellBox& b = original.bounds();
  for (int y = b.min.y(); y <= b.max.y(); ++y) {
    for (int x = b.min.x(); x <= b.max.x(); ++x) {
      if (!original.IsOccupied({x, y}) || !changed.IsFree({x, y}) || first.Probability(x, y) <= 0.5f) continue;
      ++n;
      stale += map.Probability(x, y) > 0.5f;
    }
  }
  return n ? static_cast<double>(stale) / n : NAN;
}

}  // namespace

int RunExtendExperiment(CliArgs& cli) {
  const bool help = cli.Flag("--help");
  const std::optional<WorldChoice> world = help ? std::nullopt : ChooseWorld(cli, "office");
  ExplorationOptions exploration = ExplorationFromCli(cli, 1800.0);
  const int runs = cli.Int("--runs", 1);
  const auto first_seed = static_cast<std::uint64_t>(cli.Int("--seed", 1));
  const auto changed_path = cli.Value("--changed");
  WallMoveOptions move_options;
  move_options.count = cli.Int("--moves", move_options.count);
  move_options.seed = static_cast<std::uint64_t>(cli.Int("--move-seed", 1));
  ExtendTourOptions tour;
  tour.distance = cli.Double("--distance", tour.distance);
  const auto write_changed = cli.Value("--write-changed");
  const auto json_path = cli.Value("--json");
  ProgressLine progress(ProgressWanted(cli));
  if (help) {
    std::printf("%s%s", kUsage, kExplorationFlagsUsage);
    return 0;
  }
  if (runs < 1) cli.AddError("--runs must be at least 1");
  if (changed_path && write_changed) cli.AddError("--write-changed saves a generated world, not one given by --changed");
  if (!cli.ok() || !world) {
    std::fprintf(stderr, "%s%s", cli.error().c_str(), kUsage);
    return 2;
  }
  try {
    std::optional<World> given;
    if (changed_path) given.emplace(LoadWorld(*changed_path));
    const OccupancyGrid original_truth = world->world.ToGrid();
    std::vector<double> first_psi, stale_psi, capped_psi, uncapped_psi, capped_old, uncapped_old;
    for (int r = 0; r < runs; ++r) {
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(r);
      ExplorationOptions o = exploration;
      o.simulator.seed = o.slam.filter.seed = seed;
      ExplorationRun first(world->world, world->start, o);
      const ExplorationSummary summary =
          RunExplorationWithProgress(first, "seed " + std::to_string(seed) + " first session", progress);
      auto old_map = std::make_shared<const OccupancyGrid>(first.slam().filter().best().map);
      // Walls move where the first session saw them: a change it never mapped tests nothing.
      std::vector<WallMove> moves;
      const World changed = [&] {
        if (given) return *given;
        return MoveWalls(world->world, world->start.translation(), move_options, &moves, old_map.get());
      }();
      if (write_changed) SaveWorld(changed, *write_changed + "-" + std::to_string(seed), world->start, "moved walls of " + world->path);
      const OccupancyGrid changed_truth = changed.ToGrid();
      const double v1 = BuiltMapSimilarity(*old_map, original_truth), stale = BuiltMapSimilarity(*old_map, changed_truth);

      tour.seed = seed;
      tour.mapping = o.slam.filter;
      tour.mapping.loop_closure.enabled = false;
      tour.visit_first.clear();
      for (const WallMove& m : moves) {
        // Beside the old place, on the side the piece moved away from, then beside the new place's
        // far side, which the first spot cannot see.
        const double res = changed.resolution();
        const Eigen::Vector2d move = (m.to.min - m.from.min).cast<double>() * res;
        const Eigen::Vector2d half = Eigen::Vector2d(m.from.width(), m.from.height()) * 0.5 * res;
        const Eigen::Vector2d dir = move.normalized();
        const Eigen::Vector2d centre = (m.from.min + m.from.max).cast<double>() * 0.5 * res;
        tour.visit_first.push_back(centre - dir * (std::abs(dir.dot(half)) + 0.7));
        tour.visit_first.push_back(centre + move + dir * (std::abs(dir.dot(half)) + 0.6));
      }
      const ExtendTourResult capped = RunExtendTour(changed, old_map, world->start, tour);
      ExtendTourOptions no_cap = tour;
      no_cap.mapping.prior_max_probability = 1.0;
      const ExtendTourResult uncapped = RunExtendTour(changed, old_map, world->start, no_cap);
      const double v2 = BuiltMapSimilarity(capped.map, changed_truth), v2u = BuiltMapSimilarity(uncapped.map, changed_truth);
      const double kept = StaleWalls(*old_map, capped.map, world->world, changed);
      const double kept_uncapped = StaleWalls(*old_map, uncapped.map, world->world, changed);

      std::printf("seed %llu  first: %s after %.0f s, Psi %.3f vs original (%.3f vs changed); %zu moved\n",
                  static_cast<unsigned long long>(seed), ExplorationStateName(summary.state), summary.time_s, v1, stale,
                  moves.size());
      std::printf("          extended (cap): Psi %.3f vs changed; localized after %d scans, %.0f m driven, "
                  "final error vs world %.2f m; moved-away walls kept %.0f %%\n",
                  v2, capped.localize_scans, capped.distance, capped.final_position_error, 100.0 * kept);
      std::printf("          extended (no cap): Psi %.3f vs changed; moved-away walls kept %.0f %%\n", v2u,
                  100.0 * kept_uncapped);
      if (!capped.localized || !uncapped.localized) std::printf("          warning: a tour never localized\n");
      first_psi.push_back(v1);
      stale_psi.push_back(stale);
      capped_psi.push_back(v2);
      uncapped_psi.push_back(v2u);
      capped_old.push_back(kept);
      uncapped_old.push_back(kept_uncapped);
    }
    std::printf("Psi first vs original   %s\n", SpreadText(SpreadOf(first_psi)).c_str());
    std::printf("Psi first vs changed    %s\n", SpreadText(SpreadOf(stale_psi)).c_str());
    std::printf("Psi extended vs changed %s (cap), %s (no cap)\n", SpreadText(SpreadOf(capped_psi)).c_str(),
                SpreadText(SpreadOf(uncapped_psi)).c_str());
    if (json_path) {
      WriteJsonFile(*json_path, JsonObject({{"world", JsonString(world->path)},
                                           {"psi_first_vs_original", JsonArray(first_psi)},
                                           {"psi_first_vs_changed", JsonArray(stale_psi)},
                                           {"psi_extended_vs_changed", JsonArray(capped_psi)},
                                           {"psi_extended_no_cap_vs_changed", JsonArray(uncapped_psi)},
                                           {"moved_away_walls_kept", JsonArray(capped_old)},
                                           {"moved_away_walls_kept_no_cap", JsonArray(uncapped_old)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam experiment extend: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
