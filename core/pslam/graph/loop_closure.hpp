#pragma once
// Loop closure for the particle filter (the filter stays the local estimator): every filter update
// becomes a node of a pose graph, linked to the previous one by the filter's own relative motion.
// Nodes are grouped into submaps; a node near an older submap is matched against it by branch
// and bound, and an unambiguous match becomes a loop-closure edge. After optimisation the map is
// re-rendered from the corrected poses, so that the past is corrected, not only the present.
#include <memory>
#include <optional>
#include <vector>

#include "pslam/common/parallel_for.hpp"
#include "pslam/graph/branch_and_bound_matcher.hpp"
#include "pslam/graph/loop_closure_options.hpp"
#include "pslam/graph/pose_graph.hpp"
#include "pslam/graph/submap.hpp"
#include "pslam/grid/scan_inserter.hpp"
#include "pslam/sensor/scan_points.hpp"

namespace pslam {

struct LoopClosureStats {
  int nodes = 0;
  int submaps = 0;
  int searches = 0;              // node-to-submap matches tried
  int closures = 0;              // accepted as edges
  int ambiguous = 0;             // matched, but another pose scored nearly as well
  int rivalled = 0;              // checks refused: another submap held a different place nearly as good
  int outliers = 0;              // accepted, then removed for disagreeing with the optimum
  int optimizations = 0;
  int rebuilds = 0;              // map re-rendered from corrected poses
  double search_ms = 0.0;        // wall time of the searches, optimisations and rebuilds
  double optimize_ms = 0.0;
  double rebuild_ms = 0.0;
};

// What an optimisation changed: the corrected pose of every node and the map rendered from them.
struct LoopClosureCorrection {
  std::vector<int> node_scans;     // scan index of each node
  std::vector<Pose2D> node_poses;  // optimised, in the map frame
  OccupancyGrid map;
};

class LoopCloser {
 public:
  // `pool`, when given, runs the searches of one node in parallel.
  LoopCloser(const LoopClosureOptions& options, const ScanInsertOptions& insert, double resolution,
             ThreadPool* pool = nullptr);

  // Adds the filter's pose at an update, with the scan it inserted. Returns a correction when the
  // graph was optimised and moved some node enough to re-render the map.
  // After a correction, the caller continues from the corrected pose of the newest node.
  std::optional<LoopClosureCorrection> AddNode(int scan_index, const Pose2D& pose, const ScanPoints& points);
  // Optimises the closures found since the last optimisation (at the end of a log).
  std::optional<LoopClosureCorrection> Flush();

  // The map that corrected maps are rendered on top of (a prior map in extend mode), with its floor
  // behind new surfaces forgotten as the filter does (ForgetPriorFloorBehindNewSurfaces).
  void SetBaseMap(std::shared_ptr<const OccupancyGrid> base, double forget_depth) {
    base_ = std::move(base);
    base_forget_depth_ = forget_depth;
  }

  const LoopClosureStats& stats() const { return stats_; }
  const PoseGraph& graph() const { return graph_; }

 private:
  struct Node {
    int scan_index = 0;
    ScanPoints points;
    double path_length = 0.0;     // metres travelled from the first node
  };

  void AddToSubmap(int node);
  void SearchClosures(int node);
  struct Match {
    bool found = false;             // some pose scored at least the rival threshold
    bool ambiguous = false;         // another pose in the same submap scored nearly as well
    double score = 0.0;
    double alternative_score = 0.0; // the best pose away from `measured` in this submap (0: none)
    Pose2D guess;      // the node in the submap's frame, as the graph has it
    Pose2D measured;   // ... as the match says
  };
  Match MatchAgainst(int node, int submap, double graph_distance, const MaxPoolStack& grid,
                     const std::vector<Eigen::Vector2f>& cloud) const;
  bool SamePlace(const Pose2D& a, const Pose2D& b) const;
  void Accept(int node, int submap, const Match& match);
  void Link(int a, int b, double length);
  std::vector<Eigen::Vector2f> MatchCloud(int node) const;
  // Graph distance (see LoopClosureOptions::closure_length) from `node` to every node.
  std::vector<double> GraphDistances(int node) const;
  const MaxPoolStack& SearchGrid(int submap);
  std::optional<LoopClosureCorrection> Optimize(int node);
  OccupancyGrid Render() const;

  LoopClosureOptions options_;
  ScanInserter inserter_;
  double resolution_;
  std::shared_ptr<const OccupancyGrid> base_;
  double base_forget_depth_ = 0.0;
  ThreadPool* pool_;
  PoseGraph graph_;
  std::vector<Node> nodes_;
  std::vector<Submap> submaps_;
  std::vector<std::vector<std::pair<int, double>>> links_;  // per node: (neighbour, length)
  std::vector<int> last_closure_node_;   // per submap, the node of its latest closure (-1: none)
  int last_closure_node_any_ = -1;        // the node of the latest closure to any submap
  struct CachedGrid {
    int submap = -1;
    std::unique_ptr<MaxPoolStack> stack;
    long last_used = 0;
  };
  std::vector<CachedGrid> cache_;
  long cache_clock_ = 0;
  Pose2D last_filter_pose_;              // the filter's pose at the newest node
  int pending_closures_ = 0;
  double pending_correction_ = 0.0;      // largest move a pending closure asks of its node
  int last_optimized_node_ = 0;
  LoopClosureStats stats_;
};

}  // namespace pslam
