#include "pslam/graph/loop_closure.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <queue>

#include "pslam/graph/thinned_cloud.hpp"
#include "pslam/grid/stale_prior.hpp"

namespace pslam {
namespace {

double MsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

Eigen::Matrix3d SqrtInformation(double sigma_xy, double sigma_theta) {
  return Eigen::Vector3d(1.0 / sigma_xy, 1.0 / sigma_xy, 1.0 / sigma_theta).asDiagonal();
}

}  // namespace

LoopCloser::LoopCloser(const LoopClosureOptions& options, const ScanInsertOptions& insert, double resolution,
                       ThreadPool* pool)
    : options_(options), inserter_(insert), resolution_(resolution), pool_(pool) {}

std::optional<LoopClosureCorrection> LoopCloser::AddNode(int scan_index, const Pose2D& pose, const ScanPoints& points) {
  Node node{scan_index, points, 0.0};
  int n = 0;
  if (nodes_.empty()) {
    n = graph_.AddNode(pose);
    links_.resize(1);
  } else {
    // The filter's own motion since the previous node links the two; the new node starts where
    // that motion takes the previous node's (possibly optimised) pose.
    const Pose2D motion = Between(last_filter_pose_, pose);
    n = graph_.AddNode(graph_.pose(graph_.size() - 1) * motion);
    graph_.AddEdge({n - 1, n, motion, SqrtInformation(options_.odometry_sigma_xy, options_.odometry_sigma_theta), 0.0});
    Link(n - 1, n, std::hypot(motion.x, motion.y));
    node.path_length = nodes_.back().path_length + std::hypot(motion.x, motion.y);
  }
  last_filter_pose_ = pose;
  nodes_.push_back(std::move(node));
  ++stats_.nodes;
  AddToSubmap(n);
  if (n % std::max(1, options_.check_every_nodes) == 0 && n >= last_closure_node_any_ + options_.rest_after_closure) {
    SearchClosures(n);
  }
  if (pending_closures_ > 0 && (n - last_optimized_node_ >= options_.optimize_every_nodes ||
                                pending_correction_ > options_.immediate_correction)) {
    return Optimize(n);
  }
  return std::nullopt;
}

std::optional<LoopClosureCorrection> LoopCloser::Flush() {
  if (pending_closures_ == 0) return std::nullopt;
  return Optimize(graph_.size() - 1);
}

void LoopCloser::AddToSubmap(int n) {
  if (submaps_.empty() || submaps_.back().finished) {
    submaps_.push_back(Submap{n, n, OccupancyGrid(resolution_), false});
    last_closure_node_.push_back(-1);
    ++stats_.submaps;
  }
  Submap& s = submaps_.back();
  const Pose2D local = Between(graph_.pose(s.first_node), graph_.pose(n));
  inserter_.Insert(nodes_[static_cast<std::size_t>(n)].points, local, s.grid);
  s.last_node = n;
  if (s.nodes() >= options_.nodes_per_submap) s.finished = true;
}

std::vector<Eigen::Vector2f> LoopCloser::MatchCloud(int n) const {
  ThinnedCloud cloud(options_.cloud_spacing);
  const Pose2D& at = graph_.pose(n);
  // Newest first, so that the node's own scan wins a shared cell.
  for (int k = n; k >= std::max(0, n - options_.context_nodes + 1); --k) {
    const Pose2D relative = Between(at, graph_.pose(k));
    for (const Eigen::Vector2f& p : nodes_[static_cast<std::size_t>(k)].points.hits) {
      const Eigen::Vector2d q = relative * p.cast<double>();
      if (q.norm() <= options_.cloud_max_range) cloud.Add(q);
    }
  }
  return cloud.Take();
}

void LoopCloser::Link(int a, int b, double length) {
  const auto need = static_cast<std::size_t>(std::max(a, b)) + 1;
  if (links_.size() < need) links_.resize(need);
  links_[static_cast<std::size_t>(a)].emplace_back(b, length);
  links_[static_cast<std::size_t>(b)].emplace_back(a, length);
}

std::vector<double> LoopCloser::GraphDistances(int from) const {
  std::vector<double> distance(links_.size(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> open;
  distance[static_cast<std::size_t>(from)] = 0.0;
  open.emplace(0.0, from);
  while (!open.empty()) {
    const auto [d, k] = open.top();
    open.pop();
    if (d > distance[static_cast<std::size_t>(k)]) continue;
    for (const auto& [next, length] : links_[static_cast<std::size_t>(k)]) {
      if (d + length < distance[static_cast<std::size_t>(next)]) {
        distance[static_cast<std::size_t>(next)] = d + length;
        open.emplace(d + length, next);
      }
    }
  }
  return distance;
}

void LoopCloser::SearchClosures(int n) {
  const auto start = std::chrono::steady_clock::now();
  const int eligible = static_cast<int>(submaps_.size()) - 1 - options_.recent_submaps;
  struct Candidate {
    int submap;
    double distance;        // metres, in the map
    double graph_distance;  // metres, through the graph
    bool may_close;         // false: closed a moment ago, searched only as a possible rival
  };
  std::vector<Candidate> candidates;
  const Eigen::Vector2d here = graph_.pose(n).translation();
  const std::vector<double> distance = GraphDistances(n);
  for (int s = 0; s <= eligible; ++s) {
    const Submap& submap = submaps_[static_cast<std::size_t>(s)];
    if (!submap.finished) continue;
    double nearest = 1e18, through_graph = 1e18;
    for (int k = submap.first_node; k <= submap.last_node; ++k) {
      nearest = std::min(nearest, (graph_.pose(k).translation() - here).norm());
      through_graph = std::min(through_graph, distance[static_cast<std::size_t>(k)]);
    }
    const double window = std::min(options_.base_window + options_.window_per_metre * through_graph, options_.max_window);
    const bool may_close = last_closure_node_[static_cast<std::size_t>(s)] < n - options_.nodes_per_submap / 2;
    if (!may_close && !options_.judge_across_submaps) continue;
    if (nearest <= window + 3.0) candidates.push_back({s, nearest, through_graph, may_close});
  }
  std::sort(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) { return a.distance < b.distance; });
  if (static_cast<int>(candidates.size()) > options_.max_candidates) candidates.resize(static_cast<std::size_t>(options_.max_candidates));
  const bool any_may_close = std::any_of(candidates.begin(), candidates.end(), [](const Candidate& c) { return c.may_close; });
  const std::vector<Eigen::Vector2f> cloud = any_may_close ? MatchCloud(n) : std::vector<Eigen::Vector2f>();
  if (cloud.size() >= 20) {
    // The searches are independent: run them in parallel, then judge them in candidate order, so
    // the outcome does not depend on the thread count.
    std::vector<const MaxPoolStack*> grids;
    for (const Candidate& c : candidates) grids.push_back(&SearchGrid(c.submap));
    std::vector<Match> matches(candidates.size());
    const auto search = [&](int i) {
      const Candidate& c = candidates[static_cast<std::size_t>(i)];
      matches[static_cast<std::size_t>(i)] = MatchAgainst(n, c.submap, c.graph_distance, *grids[static_cast<std::size_t>(i)], cloud);
    };
    if (pool_) pool_->ParallelFor(static_cast<int>(candidates.size()), search);
    else for (int i = 0; i < static_cast<int>(candidates.size()); ++i) search(i);
    // The node's place in the map, as each submap puts it.
    const auto in_map = [&](std::size_t i) {
      return graph_.pose(submaps_[static_cast<std::size_t>(candidates[i].submap)].first_node) * matches[i].measured;
    };
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      ++stats_.searches;
      if (matches[i].ambiguous) ++stats_.ambiguous;
      if (matches[i].found && (!best || matches[i].score > matches[*best].score)) best = i;
    }
    if (!options_.judge_across_submaps) {
      // Each submap on its own: a match with no rival inside its submap closes the loop.
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        if (matches[i].found && !matches[i].ambiguous && matches[i].score >= options_.min_score) {
          Accept(n, candidates[i].submap, matches[i]);
        }
      }
    } else if (best && matches[*best].score >= options_.min_score) {
      // The place is judged across every submap searched, not within each: in a repeating building
      // one submap may hold the robot's surroundings and another a copy of them next door. A
      // different place that scores nearly as well, in any submap, leaves the node without a closure.
      const double rival = options_.ambiguity_ratio * matches[*best].score;
      const Pose2D at = in_map(*best);
      bool rivalled = false;
      for (std::size_t i = 0; i < candidates.size(); ++i) {
        rivalled = rivalled || matches[i].alternative_score >= rival ||
                   (matches[i].found && matches[i].score >= rival && !SamePlace(in_map(i), at));
      }
      if (rivalled) {
        ++stats_.rivalled;
      } else {
        for (std::size_t i = 0; i < candidates.size(); ++i) {
          const Match& m = matches[i];
          if (candidates[i].may_close && m.found && !m.ambiguous && m.score >= options_.min_score && SamePlace(in_map(i), at)) {
            Accept(n, candidates[i].submap, m);
          }
        }
      }
    }
  }
  stats_.search_ms += MsSince(start);
}

bool LoopCloser::SamePlace(const Pose2D& a, const Pose2D& b) const {
  return std::hypot(a.x - b.x, a.y - b.y) < options_.ambiguity_distance &&
         std::abs(NormalizeAngle(a.theta - b.theta)) < options_.ambiguity_angle;
}

const MaxPoolStack& LoopCloser::SearchGrid(int submap) {
  ++cache_clock_;
  for (CachedGrid& c : cache_) {
    if (c.submap == submap) {
      c.last_used = cache_clock_;
      return *c.stack;
    }
  }
  auto stack = std::make_unique<MaxPoolStack>(submaps_[static_cast<std::size_t>(submap)].grid, options_.search_depth);
  if (static_cast<int>(cache_.size()) < std::max(1, options_.cached_search_grids)) {
    cache_.push_back({submap, std::move(stack), cache_clock_});
    return *cache_.back().stack;
  }
  CachedGrid& oldest = *std::min_element(cache_.begin(), cache_.end(),
                                         [](const CachedGrid& a, const CachedGrid& b) { return a.last_used < b.last_used; });
  oldest = {submap, std::move(stack), cache_clock_};
  return *oldest.stack;
}

LoopCloser::Match LoopCloser::MatchAgainst(int n, int s, double graph_distance, const MaxPoolStack& grid,
                                           const std::vector<Eigen::Vector2f>& cloud) const {
  Match out;
  const Submap& submap = submaps_[static_cast<std::size_t>(s)];
  out.guess = Between(graph_.pose(submap.first_node), graph_.pose(n));
  // Judged across submaps, poses a little below the acceptance score are searched too: they cannot
  // close a loop, but one may be a rival to another submap's match.
  BranchAndBoundOptions search{
      .linear_window = std::min(options_.base_window + options_.window_per_metre * graph_distance, options_.max_window),
      .angular_window = std::min(options_.base_angular_window + options_.angular_window_per_metre * graph_distance,
                                 options_.max_angular_window),
      .min_score = options_.judge_across_submaps ? options_.ambiguity_ratio * options_.min_score : options_.min_score};
  const BranchAndBoundResult best = MatchByBranchAndBound(grid, cloud, out.guess, search);
  if (!best.found) return out;
  out.found = true;
  out.score = best.score;
  out.measured = best.pose;
  // The best pose elsewhere: if it scores nearly as well, the place repeats and the match says
  // nothing about which copy the robot is in.
  search.min_score = options_.ambiguity_ratio * best.score;
  search.linear_window = std::max(search.linear_window, options_.min_rival_window);
  const BranchAndBoundResult alternative = MatchByBranchAndBound(grid, cloud, out.guess, search, [&](const Pose2D& p) {
    return SamePlace(p, best.pose);
  });
  if (alternative.found) {
    out.ambiguous = true;
    out.alternative_score = alternative.score;
    return out;
  }
  if (best.score < options_.min_score) return out;
  const ScanMatchResult refined = MatchScan(submap.grid, cloud, best.pose, options_.refine);
  if (refined.converged) out.measured = refined.pose;
  return out;
}

void LoopCloser::Accept(int n, int s, const Match& match) {
  const Submap& submap = submaps_[static_cast<std::size_t>(s)];
  graph_.AddEdge({submap.first_node, n, match.measured,
                  SqrtInformation(options_.loop_sigma_xy, options_.loop_sigma_theta), options_.huber_scale});
  Link(submap.first_node, n, options_.closure_length);
  const Pose2D asked = Between(match.guess, match.measured);
  pending_correction_ = std::max(pending_correction_, std::hypot(asked.x, asked.y));
  ++pending_closures_;
  ++stats_.closures;
  last_closure_node_[static_cast<std::size_t>(s)] = n;
  last_closure_node_any_ = n;
}

std::optional<LoopClosureCorrection> LoopCloser::Optimize(int n) {
  auto start = std::chrono::steady_clock::now();
  const std::vector<Pose2D> before = graph_.poses();
  graph_.Optimize();
  // A closure that still disagrees with everything else after optimising was a wrong match.
  const int removed = graph_.RemoveEdgesIf([&](const PoseGraphEdge& e) {
    return e.huber_scale > 0.0 && graph_.Mahalanobis(e) > options_.outlier_sigma;
  });
  if (removed > 0) {
    stats_.outliers += removed;
    graph_.Optimize();
    links_.assign(nodes_.size(), {});
    for (const PoseGraphEdge& e : graph_.edges()) {
      Link(e.from, e.to, e.huber_scale > 0.0 ? options_.closure_length : std::hypot(e.measurement.x, e.measurement.y));
    }
  }
  ++stats_.optimizations;
  stats_.optimize_ms += MsSince(start);
  pending_closures_ = 0;
  pending_correction_ = 0.0;
  last_optimized_node_ = n;

  double moved = 0.0, turned = 0.0;
  for (int k = 0; k < graph_.size(); ++k) {
    const Pose2D d = Between(before[static_cast<std::size_t>(k)], graph_.pose(k));
    moved = std::max(moved, std::hypot(d.x, d.y));
    turned = std::max(turned, std::abs(d.theta));
  }
  if (moved < options_.rebuild_translation && turned < options_.rebuild_rotation) return std::nullopt;

  start = std::chrono::steady_clock::now();
  LoopClosureCorrection correction;
  correction.node_scans.reserve(nodes_.size());
  for (const Node& node : nodes_) correction.node_scans.push_back(node.scan_index);
  correction.node_poses = graph_.poses();
  correction.map = Render();
  last_filter_pose_ = graph_.pose(n);  // the filter continues from the corrected pose
  ++stats_.rebuilds;
  stats_.rebuild_ms += MsSince(start);
  return correction;
}

OccupancyGrid LoopCloser::Render() const {
  OccupancyGrid map = base_ ? *base_ : OccupancyGrid(resolution_);
  for (int k = 0; k < graph_.size(); ++k) {
    const ScanPoints& points = nodes_[static_cast<std::size_t>(k)].points;
    inserter_.Insert(points, graph_.pose(k), map);
    if (base_) ForgetPriorFloorBehindNewSurfaces(points, graph_.pose(k), *base_, base_forget_depth_, map);
  }
  return map;
}

}  // namespace pslam
