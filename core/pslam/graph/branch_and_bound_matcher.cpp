#include "pslam/graph/branch_and_bound_matcher.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace pslam {
namespace {
constexpr std::uint8_t kUnknownValue = MaxPoolStack::kOutside;
}  // namespace

MaxPoolStack::MaxPoolStack(const OccupancyGrid& grid, int depth) : resolution_(grid.resolution()) {
  const CellBox box = grid.KnownBounds();
  levels_.resize(static_cast<std::size_t>(depth) + 1);
  if (box.empty()) return;
  // Below the grid, block corners reach 2^depth cells out; above it, the field's reach is 2 cells.
  // The same padding above as well lets the search sum a cloud that overhangs the known cells
  // without bounds checks.
  const int pad = 1 << depth;
  origin_ = box.min - Eigen::Vector2i::Constant(pad);
  width_ = box.width() + 2 * pad + 2;
  height_ = box.height() + 2 * pad + 2;
  const std::size_t n = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  // Unknown cells (outside what the submap saw) hold a neutral value, below a hit: a point there
  // neither supports nor refutes a pose, while a point in observed free space refutes it.
  std::vector<std::uint8_t>& base = levels_[0];
  base.assign(n, kUnknownValue);
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      if (grid.IsKnown(x, y)) base[static_cast<std::size_t>(y - origin_.y()) * width_ + (x - origin_.x())] = 0;
    }
  }
  // Level 0 is a likelihood field of the occupied cells: 1 on them, falling off as a Gaussian of
  // one cell's deviation, so that a point a cell off a wall (aliasing, a slightly different view)
  // still counts for most of a hit, and free and unknown space for nothing.
  constexpr int kReach = 2;
  std::array<std::uint8_t, (2 * kReach + 1) * (2 * kReach + 1)> kernel{};
  for (int dy = -kReach; dy <= kReach; ++dy) {
    for (int dx = -kReach; dx <= kReach; ++dx) {
      kernel[static_cast<std::size_t>((dy + kReach) * (2 * kReach + 1) + dx + kReach)] =
          static_cast<std::uint8_t>(std::lround(255.0 * std::exp(-0.5 * (dx * dx + dy * dy))));
    }
  }
  for (int y = box.min.y(); y <= box.max.y(); ++y) {
    for (int x = box.min.x(); x <= box.max.x(); ++x) {
      const OccupancyGrid::Cell c = grid.At(x, y);
      if (c == OccupancyGrid::kUnknown || c <= 0) continue;  // only likely-occupied cells attract points
      for (int dy = -kReach; dy <= kReach; ++dy) {
        for (int dx = -kReach; dx <= kReach; ++dx) {
          const int ix = x + dx - origin_.x(), iy = y + dy - origin_.y();
          if (ix < 0 || iy < 0 || ix >= width_ || iy >= height_) continue;
          std::uint8_t& v = base[static_cast<std::size_t>(iy) * width_ + ix];
          v = std::max(v, kernel[static_cast<std::size_t>((dy + kReach) * (2 * kReach + 1) + dx + kReach)]);
        }
      }
    }
  }
  // Level h holds the max over [x, x + 2^h) x [y, y + 2^h): four shifted maxima of level h - 1.
  for (int h = 1; h <= depth; ++h) {
    const int s = 1 << (h - 1);
    const std::vector<std::uint8_t>& prev = levels_[static_cast<std::size_t>(h - 1)];
    std::vector<std::uint8_t>& level = levels_[static_cast<std::size_t>(h)];
    level.assign(n, 0);
    const auto at = [&](int x, int y) -> std::uint8_t {
      return x < width_ && y < height_ ? prev[static_cast<std::size_t>(y) * width_ + x] : kUnknownValue;
    };
    for (int y = 0; y < height_; ++y) {
      for (int x = 0; x < width_; ++x) {
        level[static_cast<std::size_t>(y) * width_ + x] =
            std::max({at(x, y), at(x + s, y), at(x, y + s), at(x + s, y + s)});
      }
    }
  }
  // Level-h values are read at the low corner of a block, which may lie up to 2^h - 1 cells below
  // the grid: the padding keeps those reads inside the arrays.
}

namespace {

struct Candidate {
  int rotation = 0;
  int dx = 0, dy = 0;   // cell offset of the block's low corner
  int score = 0;
};

struct RotatedScan {
  double theta = 0.0;
  std::vector<Eigen::Vector2i> cells;  // points at the guess translation, this rotation
  // The same points as indices into a level of the stack, and their bounding box in its array.
  std::vector<int> offsets;
  int min_x = 0, max_x = 0, min_y = 0, max_y = 0;
};

class Search {
 public:
  Search(const MaxPoolStack& stack, std::vector<RotatedScan> scans, int window_cells, int min_score, bool first_found,
         const std::function<bool(const Candidate&)>& excluded)
      : stack_(stack), scans_(std::move(scans)), window_(window_cells), best_score_(min_score - 1),
        first_found_(first_found), excluded_(excluded) {
    const Eigen::Vector2i& origin = stack_.origin();
    for (RotatedScan& s : scans_) {
      if (s.cells.empty()) continue;
      s.offsets.reserve(s.cells.size());
      s.min_x = s.max_x = s.cells.front().x() - origin.x();
      s.min_y = s.max_y = s.cells.front().y() - origin.y();
      for (const Eigen::Vector2i& c : s.cells) {
        const int ix = c.x() - origin.x(), iy = c.y() - origin.y();
        s.offsets.push_back(iy * stack_.width() + ix);
        s.min_x = std::min(s.min_x, ix), s.max_x = std::max(s.max_x, ix);
        s.min_y = std::min(s.min_y, iy), s.max_y = std::max(s.max_y, iy);
      }
    }
  }

  void Run() {
    const int top = stack_.depth();
    const int step = 1 << top;
    std::vector<Candidate> roots;
    for (int r = 0; r < static_cast<int>(scans_.size()); ++r) {
      for (int dy = -window_; dy <= window_; dy += step) {
        for (int dx = -window_; dx <= window_; dx += step) roots.push_back({r, dx, dy, Score(top, r, dx, dy)});
      }
    }
    Descend(top, roots.data(), roots.data() + roots.size());
  }
  bool found() const { return found_; }
  const Candidate& best() const { return best_; }

 private:
  int Score(int h, int r, int dx, int dy) const {
    const RotatedScan& scan = scans_[static_cast<std::size_t>(r)];
    int sum = 0;
    if (scan.min_x + dx >= 0 && scan.max_x + dx < stack_.width() && scan.min_y + dy >= 0 && scan.max_y + dy < stack_.height()) {
      // Every point inside the arrays (the common case): no bounds to check per point.
      const std::uint8_t* level = stack_.Level(h);
      const int shift = dy * stack_.width() + dx;
      for (const int offset : scan.offsets) sum += level[offset + shift];
      return sum;
    }
    for (const Eigen::Vector2i& c : scan.cells) sum += stack_.At(h, c.x() + dx, c.y() + dy);
    return sum;
  }

  void Descend(int h, Candidate* begin, Candidate* end) {
    std::sort(begin, end, [](const Candidate& a, const Candidate& b) { return a.score > b.score; });
    for (const Candidate* it = begin; it != end; ++it) {
      const Candidate& c = *it;
      if (c.score <= best_score_) return;  // sorted: nothing after this can beat the best either
      if (found_ && first_found_) return;
      if (h == 0) {
        if (excluded_ && excluded_(c)) continue;
        best_ = c;
        best_score_ = c.score;
        found_ = true;
        continue;
      }
      const int half = 1 << (h - 1);
      std::array<Candidate, 4> children;
      int count = 0;
      for (int oy : {0, half}) {
        for (int ox : {0, half}) {
          const int dx = c.dx + ox, dy = c.dy + oy;
          if (dx > window_ || dy > window_) continue;
          children[static_cast<std::size_t>(count++)] = {c.rotation, dx, dy, Score(h - 1, c.rotation, dx, dy)};
        }
      }
      Descend(h - 1, children.data(), children.data() + count);
    }
  }

  const MaxPoolStack& stack_;
  std::vector<RotatedScan> scans_;
  int window_;
  int best_score_;
  bool first_found_;
  std::function<bool(const Candidate&)> excluded_;
  Candidate best_;
  bool found_ = false;
};

}  // namespace

BranchAndBoundResult MatchByBranchAndBound(const MaxPoolStack& stack, const std::vector<Eigen::Vector2f>& points,
                                           const Pose2D& guess, const BranchAndBoundOptions& options,
                                           const std::function<bool(const Pose2D&)>& excluded) {
  BranchAndBoundResult out;
  if (points.empty()) return out;
  const double res = stack.resolution();
  double max_range = 0.0;
  for (const Eigen::Vector2f& p : points) max_range = std::max(max_range, static_cast<double>(p.norm()));
  // An angular step that moves the farthest point by at most one cell.
  const double angular_step = std::max(1e-3, std::acos(std::clamp(1.0 - res * res / (2.0 * max_range * max_range), -1.0, 1.0)));
  const int rotations = static_cast<int>(std::ceil(options.angular_window / angular_step));
  std::vector<RotatedScan> scans;
  scans.reserve(static_cast<std::size_t>(2 * rotations + 1));
  for (int k = -rotations; k <= rotations; ++k) {
    RotatedScan s;
    s.theta = guess.theta + k * angular_step;
    const Pose2D at(guess.x, guess.y, s.theta);
    s.cells.reserve(points.size());
    for (const Eigen::Vector2f& p : points) {
      const Eigen::Vector2d w = at * p.cast<double>();
      s.cells.emplace_back(static_cast<int>(std::floor(w.x() / res)), static_cast<int>(std::floor(w.y() / res)));
    }
    scans.push_back(std::move(s));
  }
  const int window_cells = static_cast<int>(std::ceil(options.linear_window / res));
  const int min_score = static_cast<int>(std::ceil(options.min_score * 255.0 * static_cast<double>(points.size())));
  const auto to_pose = [&](int rotation, int dx, int dy) {
    return Pose2D(guess.x + dx * res, guess.y + dy * res, scans[static_cast<std::size_t>(rotation)].theta);
  };
  std::function<bool(const Candidate&)> reject;
  if (excluded) reject = [&](const Candidate& c) { return excluded(to_pose(c.rotation, c.dx, c.dy)); };
  Search search(stack, scans, window_cells, min_score, options.first_above_min_score, reject);
  search.Run();
  if (!search.found()) return out;
  const Candidate& best = search.best();
  out.found = true;
  out.pose = to_pose(best.rotation, best.dx, best.dy);
  out.score = best.score / (255.0 * static_cast<double>(points.size()));
  return out;
}

}  // namespace pslam
