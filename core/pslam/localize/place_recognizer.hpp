#pragma once
// Global localization by place recognition: the scans of the last few metres, joined by odometry
// into one local cloud, are searched for over the whole fixed map at every heading with the
// branch-and-bound correlative matcher (as Cartographer localizes on a frozen map). A cloud spans
// far more of a building than one scan, so it tells look-alike rooms apart once the robot has
// seen what differs between them; until then the best place has a rival that explains the cloud
// nearly as well, and the search says so instead of guessing. In a world that is symmetric (a
// square maze looks the same turned by 90 degrees) the rival never goes away: no sensor can tell
// those places apart, and the localizer should not claim to.
#include <Eigen/Core>
#include <deque>
#include <vector>

#include "pslam/common/pose2d.hpp"
#include "pslam/graph/branch_and_bound_matcher.hpp"
#include "pslam/grid/occupancy_grid.hpp"

namespace pslam {

// A known map cell below this occupancy is free space a robot may stand in: a loaded map's free
// cells read 0.12, a built map's well under 0.5; a cell hardly ever seen stays near 0.5.
constexpr float kFreeCellProbability = 0.25f;

struct PlaceRecognitionOptions {
  bool enabled = true;
  // Metres of travel whose scans form the searched cloud. With scan odometry (MclOptions) 16 m
  // stay straight enough to match, and hold a place's telling feature longer than 8 m: the office
  // converged after 24 m on average instead of 35.
  double cloud_travel = 16.0;
  double cloud_spacing = 0.1;      // m between kept cloud points
  int max_points = 400;            // the cloud is thinned evenly to at most this many
  double first_search_after = 1.0; // m of travel before the first search
  double search_every = 2.0;       // m of travel between searches while no place is recognized
  double search_resolution = 0.1;  // m per cell of the searched map (coarsened from the map's own)
  int search_depth = 6;            // max-pooled levels of the search (2^6 cells)
  double min_score = 0.6;          // mean field value at the cloud's points for a place to count
  // A place is recognized only when no pose this far from it scores within this ratio of it.
  double ambiguity_distance = 1.0;  // m
  double ambiguity_angle = 0.3;     // rad
  double ambiguity_ratio = 0.93;
  // The same for a cloud taken from one spot, the robot turning in place (under
  // in_place_travel of travel): it has no odometry drift to allow for, so a smaller margin
  // tells places apart. At 0.96 a look around at the office's corridor end is unique; after
  // driving, 0.96 let a drifted cloud match a wrong place there.
  double ambiguity_ratio_in_place = 0.96;
  double in_place_travel = 0.5;     // m
};

struct PlaceMatch {
  enum class Outcome { kNone, kAmbiguous, kUnique };
  Outcome outcome = Outcome::kNone;
  Pose2D pose;                     // the robot's pose in the map at the newest scan
  double score = 0.0;
  Pose2D rival;                    // a pose away from 'pose' scoring within the ambiguity ratio (the first found)
  double rival_score = 0.0;
  int points = 0;                  // in the searched cloud
};

class PlaceRecognizer {
 public:
  PlaceRecognizer(const OccupancyGrid& map, const PlaceRecognitionOptions& options);

  // Forgets the cloud: the robot may be anywhere (a start, a kidnapping).
  void Reset();
  // A scan's endpoints in the robot frame, with the robot's odometry pose at that scan.
  void Add(const std::vector<Eigen::Vector2f>& hits, const Pose2D& odometry);
  // Whether the robot travelled far enough, or turned nearly all the way round, since the start or
  // the last search.
  bool SearchDue() const;
  // Searches the map for the cloud.
  PlaceMatch Search();

  double travelled() const { return travelled_; }
  bool searched() const { return searched_at_ >= 0.0; }  // since the last Reset

 private:
  struct Scan {
    Pose2D odometry;
    double travelled = 0.0;
    std::vector<Eigen::Vector2f> hits;
  };
  std::vector<Eigen::Vector2f> Cloud() const;  // in the frame of the newest scan
  bool StandsFree(const Pose2D& robot) const;

  PlaceRecognitionOptions options_;
  MaxPoolStack stack_;
  // The map at the search's resolution, each cell its freest: a place puts the robot on free floor.
  OccupancyGrid floor_;
  Pose2D guess_;                   // the map's centre: the search spans the map from it
  double window_ = 0.0;            // m each way
  std::deque<Scan> scans_;
  double travelled_ = 0.0;
  double turned_ = 0.0;            // rad, summed over the scans since the last Reset
  double searched_at_ = -1.0;      // travel at the last search, < 0 before the first
  double searched_turn_ = 0.0;     // turning at the last search
};

}  // namespace pslam
