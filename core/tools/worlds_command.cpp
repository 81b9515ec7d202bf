// `pslam worlds generate`: writes a generated floor plan (core/pslam/sim/floorplan.hpp) as a
// map_server world, with its start pose in the YAML like the shipped worlds.
#include <algorithm>
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "commands.hpp"
#include "pslam/sim/floorplan.hpp"
#include "pslam/sim/world_file.hpp"

namespace pslam {
namespace {

std::string FamilyList() {
  std::string out;
  for (const FloorPlanFamily f : AllFloorPlanFamilies()) out += (out.empty() ? "" : ", ") + std::string(FloorPlanFamilyName(f));
  return out;
}

void PrintUsage(std::FILE* to) {
  std::fprintf(to,
               "usage: pslam worlds generate --family F --seed S [--count N] --out PREFIX\n"
               "  Writes PREFIX.yaml and PREFIX.pgm (with --count, PREFIX_<seed> for seeds S .. S+N-1): a generated\n"
               "  floor plan, the same for the same family and seed. Families: %s.\n",
               FamilyList().c_str());
}

}  // namespace

int RunWorldsCommand(const std::vector<std::string>& args) {
  const std::string action = args.empty() ? "" : args.front();
  CliArgs cli(std::vector<std::string>(args.begin() + (args.empty() ? 0 : 1), args.end()));
  if (action != "generate" || cli.Flag("--help")) {
    const bool help = action.empty() || action == "--help" || action == "-h" || action == "generate";
    if (!help) std::fprintf(stderr, "unknown action '%s'\n", action.c_str());
    PrintUsage(help ? stdout : stderr);
    return help ? 0 : 2;
  }
  const std::string family_name = cli.Value("--family").value_or("");
  const int seed = cli.Int("--seed", 1);
  const int count = cli.Int("--count", 0);
  const std::string out = cli.Value("--out").value_or("");
  const auto family = ParseFloorPlanFamily(family_name);
  if (!family) cli.AddError("--family must be one of " + FamilyList() + ", got '" + family_name + "'");
  if (seed < 0) cli.AddError("--seed must not be negative");
  if (count < 0) cli.AddError("--count must not be negative");
  if (out.empty()) cli.AddError("--out PREFIX is required");
  if (!cli.ok()) {
    std::fprintf(stderr, "%s", cli.error().c_str());
    PrintUsage(stderr);
    return 2;
  }
  try {
    for (int i = 0; i < std::max(count, 1); ++i) {
      const FloorPlan plan = GenerateFloorPlan(*family, static_cast<std::uint64_t>(seed + i));
      const std::string prefix = count > 0 ? out + "_" + std::to_string(seed + i) : out;
      SaveWorld(plan.world, prefix, plan.start, plan.description);
      std::printf("%s.yaml: %s, %.0f m^2, start (%.2f, %.2f, %.3f)\n", prefix.c_str(), plan.description.c_str(),
                  plan.outline_area_m2, plan.start.x, plan.start.y, plan.start.theta);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam worlds generate: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
