// `pslam experiment extend`: lifelong mapping. A first session explores a world and maps it; a few
// walls move; a second session extends the first map on the changed world. The new version's Psi
// against the changed world is set against the first version's Psi against the original, with the
// prior's confidence capped (what extend mode does) and not (what shows whether old walls stay).
#include <cstdio>
#include <memory>
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
    "  world changes: --changed loads the changed world, else N (3) straight pieces of interior wall\n"
    "  move 1 m sideways (deterministic for --move-seed, 1; --write-changed saves that world). A\n"
    "  second session localizes on the first version in the changed world, then extends it while\n"
    "  touring the places that changed and M (120) m of random goals, with the prior's confidence\n"
    "  capped and again without the cap. Prints Psi (occupied cells, one-cell tolerance) of each\n"
    "  map against its world, for seeds S, S+1, ... (--runs N, default 1), and for generated moves\n"
    "  the share of the old places still mapped as wall and of the new places mapped as wall.\n";

// The share of a box's cells that 'map' says are occupied.
double OccupiedShare(const OccupancyGrid& map, const CellBox& box) {
  int occupied = 0, n = 0;
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x, ++n) occupied += map.Probability(x, y) > 0.5f;
  }
  return n ? static_cast<double>(occupied) / n : 0.0;
}

struct Scores {
  double psi = 0.0;
  double old_place_wall = 0.0;  // mean over moved pieces
  double new_place_wall = 0.0;
};

Scores Score(const OccupancyGrid& map, const OccupancyGrid& truth, const std::vector<WallMove>& moves) {
  Scores s;
  s.psi = BuiltMapSimilarity(map, truth);
  for (const WallMove& m : moves) {
    s.old_place_wall += OccupiedShare(map, m.from) / static_cast<double>(moves.size());
    s.new_place_wall += OccupiedShare(map, m.to) / static_cast<double>(moves.size());
  }
  return s;
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
    std::vector<WallMove> moves;
    const World changed = changed_path ? LoadWorld(*changed_path)
                                       : MoveWalls(world->world, world->start.translation(), move_options, &moves);
    if (write_changed) SaveWorld(changed, *write_changed, world->start, "moved walls of " + world->path);
    const OccupancyGrid original_truth = world->world.ToGrid(), changed_truth = changed.ToGrid();
    std::printf("%s: %zu wall piece(s) moved%s\n", world->path.c_str(), moves.size(),
                changed_path ? (" (" + *changed_path + ")").c_str() : "");
    std::vector<double> first_psi, stale_psi, capped_psi, uncapped_psi, capped_old, uncapped_old, capped_new;
    for (int r = 0; r < runs; ++r) {
      const std::uint64_t seed = first_seed + static_cast<std::uint64_t>(r);
      ExplorationOptions o = exploration;
      o.simulator.seed = o.slam.filter.seed = seed;
      ExplorationRun first(world->world, world->start, o);
      const ExplorationSummary summary =
          RunExplorationWithProgress(first, "seed " + std::to_string(seed) + " first session", progress);
      auto old_map = std::make_shared<const OccupancyGrid>(first.slam().filter().best().map);
      const Scores v1 = Score(*old_map, original_truth, {});
      const Scores stale = Score(*old_map, changed_truth, moves);

      tour.seed = seed;
      tour.mapping = o.slam.filter;
      tour.mapping.loop_closure.enabled = false;
      tour.visit_first.clear();
      for (const WallMove& m : moves) tour.visit_first.push_back((m.from.min + m.from.max).cast<double>() * 0.5 * changed.resolution());
      const ExtendTourResult capped = RunExtendTour(changed, old_map, world->start, tour);
      ExtendTourOptions no_cap = tour;
      no_cap.mapping.prior_max_probability = 1.0;
      const ExtendTourResult uncapped = RunExtendTour(changed, old_map, world->start, no_cap);
      const Scores v2 = Score(capped.map, changed_truth, moves), v2u = Score(uncapped.map, changed_truth, moves);

      std::printf("seed %llu  first: %s after %.0f s, Psi %.3f vs original (%.3f vs changed)\n",
                  static_cast<unsigned long long>(seed), ExplorationStateName(summary.state), summary.time_s, v1.psi,
                  stale.psi);
      std::printf("          extended (cap): Psi %.3f vs changed; localized after %d scans, %.0f m driven, "
                  "final error %.2f m; old places wall %.0f %%, new places wall %.0f %%\n",
                  v2.psi, capped.localize_scans, capped.distance, capped.final_position_error,
                  100.0 * v2.old_place_wall, 100.0 * v2.new_place_wall);
      std::printf("          extended (no cap): Psi %.3f vs changed; old places wall %.0f %%, new places wall %.0f %%\n",
                  v2u.psi, 100.0 * v2u.old_place_wall, 100.0 * v2u.new_place_wall);
      if (!capped.localized || !uncapped.localized) std::printf("          warning: a tour never localized\n");
      first_psi.push_back(v1.psi);
      stale_psi.push_back(stale.psi);
      capped_psi.push_back(v2.psi);
      uncapped_psi.push_back(v2u.psi);
      capped_old.push_back(v2.old_place_wall);
      uncapped_old.push_back(v2u.old_place_wall);
      capped_new.push_back(v2.new_place_wall);
    }
    std::printf("Psi first vs original   %s\n", SpreadText(SpreadOf(first_psi)).c_str());
    std::printf("Psi first vs changed    %s\n", SpreadText(SpreadOf(stale_psi)).c_str());
    std::printf("Psi extended vs changed %s (cap), %s (no cap)\n", SpreadText(SpreadOf(capped_psi)).c_str(),
                SpreadText(SpreadOf(uncapped_psi)).c_str());
    if (json_path) {
      WriteJsonFile(*json_path, JsonObject({{"world", JsonString(world->path)},
                                           {"moves", JsonNumber(static_cast<double>(moves.size()))},
                                           {"psi_first_vs_original", JsonArray(first_psi)},
                                           {"psi_first_vs_changed", JsonArray(stale_psi)},
                                           {"psi_extended_vs_changed", JsonArray(capped_psi)},
                                           {"psi_extended_no_cap_vs_changed", JsonArray(uncapped_psi)},
                                           {"old_place_wall_share", JsonArray(capped_old)},
                                           {"old_place_wall_share_no_cap", JsonArray(uncapped_old)},
                                           {"new_place_wall_share", JsonArray(capped_new)}}));
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam experiment extend: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
