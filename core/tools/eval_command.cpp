// `pslam eval`: the two accuracy measures of the project, as a table or as one JSON object.
#include <cstdio>
#include <exception>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "cli_args.hpp"
#include "commands.hpp"
#include "pslam/eval/map_divergence.hpp"
#include "pslam/eval/relative_pose_error.hpp"
#include "pslam/eval/trajectory_io.hpp"
#include "pslam/experiment/map_alignment.hpp"
#include "pslam/io/map_io.hpp"

namespace pslam {
namespace {

constexpr const char* kUsage =
    "usage: pslam eval --trajectory FILE --relations FILE [--stamp-tolerance S] [--max-missing PERCENT] [--json]\n"
    "       pslam eval --map MAP.yaml --reference REFERENCE.yaml [--json]\n"
    "  The first form gives the relative pose error (Kuemmerle et al. 2009) of a trajectory\n"
    "  ('timestamp x y theta' lines) against ground-truth relations ('t1 t2 x y z roll pitch yaw').\n"
    "  A relation stamp takes the pose with the nearest stamp within S seconds (default 0.001);\n"
    "  relations without one are counted as missing, and more than PERCENT % of them (default 5)\n"
    "  is an error.\n"
    "  The second compares a map with a reference (a floor plan, or another session's map of the\n"
    "  same frame): the KL divergence D_KL(reference || map) of P-SLAM eq. 24 (lower is better), and\n"
    "  Psi (eq. 5) of the map's walls against the reference's over the cells the map knows, as it\n"
    "  lies and once laid onto the reference (the rigid motion found, within 0.5 m and 0.05 rad):\n"
    "  the first says how well it sits, the second how consistent it is. Both maps need one resolution.\n";

int UsageError(const std::string& message) {
  std::fprintf(stderr, "%s%s", message.c_str(), kUsage);
  return 2;
}

struct RpeOptions {
  double stamp_tolerance_s = kDefaultStampTolerance;
  double max_missing_percent = 5.0;
};

int PrintRpe(const std::string& trajectory_path, const std::string& relations_path, const RpeOptions& options,
             bool json) {
  const RpeResult r =
      ComputeRpe(ReadTrajectory(trajectory_path), ReadRelations(relations_path), options.stamp_tolerance_s);
  if (const auto problem = TooManyMissing(r, options.max_missing_percent)) {
    std::fprintf(stderr, "pslam eval: relations %s against trajectory %s: %s (see --stamp-tolerance, --max-missing)\n",
                 relations_path.c_str(), trajectory_path.c_str(), problem->c_str());
    return 1;
  }
  const double missing_percent = 100.0 * static_cast<double>(r.missing) / static_cast<double>(r.used + r.missing);
  if (json) {
    std::printf(
        "{\"used\": %zu, \"missing\": %zu, \"trans_mean_m\": %.9g, \"trans_std_m\": %.9g, \"trans_max_m\": %.9g, "
        "\"rot_mean_deg\": %.9g, \"rot_std_deg\": %.9g, \"rot_max_deg\": %.9g, \"trans2_mean_m2\": %.9g, "
        "\"trans2_std_m2\": %.9g, \"rot2_mean_deg2\": %.9g, \"rot2_std_deg2\": %.9g, \"relations\": %zu, "
        "\"missing_percent\": %.9g, \"stamp_tolerance_s\": %.9g, \"max_stamp_offset_s\": %.9g}\n",
        r.used, r.missing, r.trans_mean, r.trans_std, r.trans_max, r.rot_mean_deg, r.rot_std_deg, r.rot_max_deg,
        r.trans2_mean, r.trans2_std, r.rot2_mean_deg2, r.rot2_std_deg2, r.used + r.missing, missing_percent,
        r.stamp_tolerance_s, r.max_stamp_offset_s);
    return 0;
  }
  std::printf("relations: %zu used, %zu missing (%.1f %%; stamps matched within %g s, largest offset %.6f s)\n", r.used,
              r.missing, missing_percent, r.stamp_tolerance_s, r.max_stamp_offset_s);
  std::printf("%-24s %12s   %-12s %12s\n", "relative pose error", "mean", "std", "max");
  const auto row = [](const char* name, double mean, double std, double max) {
    std::printf("%-24s %12.6f \xC2\xB1 %-12.6f %12.6f\n", name, mean, std, max);  // U+00B1 '±'
  };
  row("translation [m]", r.trans_mean, r.trans_std, r.trans_max);
  row("rotation [deg]", r.rot_mean_deg, r.rot_std_deg, r.rot_max_deg);
  row("translation^2 [m^2]", r.trans2_mean, r.trans2_std, r.trans_max * r.trans_max);
  row("rotation^2 [deg^2]", r.rot2_mean_deg2, r.rot2_std_deg2, r.rot_max_deg * r.rot_max_deg);
  return 0;
}

int PrintMapComparison(const std::string& map_path, const std::string& reference_path, bool json) {
  const OccupancyGrid map = LoadMap(map_path), reference = LoadMap(reference_path);
  const MapDivergence d = ComputeMapDivergence(reference, map);  // throws unless both share a resolution
  const MapAlignment a = AlignMap(map, reference);
  if (json) {
    std::printf("{\"kl\": %.9g, \"cells\": %zu, \"psi\": %.6f, \"psi_laid_onto\": %.6f, \"laid_onto_shift_m\": %.6f, "
                "\"laid_onto_turn_rad\": %.6f}\n",
                d.kl, d.cells, a.psi, a.laid_psi, a.centre_shift, a.move.theta);
    return 0;
  }
  std::printf("KL divergence D_KL(reference || map): %.6g nats over %zu reference cells\n", d.kl, d.cells);
  std::printf("Psi of the map's walls against the reference's: %.3f as it lies, %.3f laid onto it\n", a.psi, a.laid_psi);
  std::printf("laid onto it: the map's middle moved %.3f m and turned %.2f deg\n", a.centre_shift,
              a.move.theta * 180.0 / std::numbers::pi);
  return 0;
}

}  // namespace

int RunEvalCommand(const std::vector<std::string>& args) {
  CliArgs cli(args);
  const bool help = cli.Flag("--help") || cli.Flag("-h");
  const bool json = cli.Flag("--json");
  const std::optional<std::string> trajectory = cli.Value("--trajectory"), relations = cli.Value("--relations");
  const std::optional<std::string> map = cli.Value("--map"), reference = cli.Value("--reference");
  RpeOptions rpe_options;
  rpe_options.stamp_tolerance_s = cli.Double("--stamp-tolerance", rpe_options.stamp_tolerance_s);
  rpe_options.max_missing_percent = cli.Double("--max-missing", rpe_options.max_missing_percent);
  if (!(rpe_options.stamp_tolerance_s >= 0.0)) cli.AddError("--stamp-tolerance must be >= 0 seconds");
  if (!(rpe_options.max_missing_percent >= 0.0)) cli.AddError("--max-missing must be a percentage >= 0");
  if (!cli.ok()) return UsageError(cli.error());
  if (help) {
    std::printf("%s", kUsage);
    return 0;
  }
  const bool rpe_mode = trajectory || relations, map_mode = map || reference;
  if (rpe_mode == map_mode) return UsageError("give either --trajectory and --relations, or --map and --reference\n");
  if (rpe_mode && !(trajectory && relations)) return UsageError("--trajectory and --relations go together\n");
  if (map_mode && !(map && reference)) return UsageError("--map and --reference go together\n");
  try {
    return rpe_mode ? PrintRpe(*trajectory, *relations, rpe_options, json) : PrintMapComparison(*map, *reference, json);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pslam eval: %s\n", e.what());
    return 1;
  }
}

}  // namespace pslam
