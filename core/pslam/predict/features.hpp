#pragma once
// Line and corner features of a map raster (P-SLAM paper, section III-A-1 and Fig. 3/4): lines by
// the probabilistic Hough transform, corners from image gradients, and for each corner
// the directions phi1, phi2 of the two walls that form it, which give the four candidate angles
// of eq. 2.
//
// Steps, all on the image of occupied cells (free and unknown cells are background: only
// structure makes features, so a frontier between free and unknown space never does):
// 1. Lines: cv::HoughLinesP; each segment's direction is then refitted (least squares with a Huber
//    loss) to the occupied cells within two cells of it, because on walls a few cells thick the
//    Hough segment may join opposite edges and lean by several degrees, and a degree of error in
//    phi moves the far side of a 10 m region by more than a cell.
// 2. Corners: the corner response of image gradients over a small window (cv::goodFeaturesToTrack,
//    with non-maximum suppression and a threshold relative to the strongest corner), on the
//    occupied image after a small Gaussian blur (a one-cell wall is a step on both sides; the
//    blur makes its response smooth). The response is Shi-Tomasi's minimum eigenvalue by
//    default rather than Harris': a wall end has one strong and one weak gradient direction,
//    which Harris' det - k trace^2 nearly cancels; on a 45-degree stub we measured a Harris
//    response a tenth of the axis-aligned one, and lost the control point. On maps finer than
//    'corner_resolution_m' the image is first average-pooled to that resolution (the paper's
//    maps are 0.1 m): the response is the most expensive step, a 2x2 pooling cuts it fourfold,
//    and the position is refined at full resolution in step 4.
// 3. Arms: a segment belongs to a corner when its body passes within 'arm_search_radius_m' of
//    it. The corner splits the segment into up to two rays (an L corner has one per wall, a T
//    junction three); rays shorter than 'min_arm_length_m' are dropped. Rays are clustered by
//    direction (thick walls yield several parallel segments), and phi1 is the direction with the
//    most wall length, phi2 the strongest direction that is neither parallel nor opposite to it.
//    With no such direction phi2 = phi1 + 90 degrees (the paper's corners are formed by two
//    segments; a wall end is treated as a right-angle corner). A corner with no ray is dropped.
//    Directions are directed (the ray leaves the corner), so theta = phi1 - phi2 is a rotation,
//    not a rotation up to 180 degrees.
// 4. Position: for a two-armed corner, the intersection of the two refitted lines replaces the
//    response peak, which the blur shifts towards the inside of the corner; a one-armed corner is
//    projected onto its line (not moved to its segment's end point, which depends on where Hough
//    cut the segment: two copies of one structure must yield the same control point). A
//    one-armed corner with unexplored cells just past its end is dropped: the wall was cut by the
//    edge of the explored map, so its "end" is a frontier artefact that would otherwise be the
//    control point nearest to every frontier.
#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "pslam/predict/map_raster.hpp"

namespace pslam {

struct FeatureOptions {
  // Hough lines.
  double min_line_length_m = 0.5;
  double max_line_gap_m = 0.15;     // gaps from missing wall cells or doors narrower than this are bridged
  double hough_vote_fraction = 0.5; // accumulator threshold, as a fraction of the cells of a minimum-length line
  // Corners.
  bool use_harris = false;          // false: Shi-Tomasi minimum eigenvalue (step 2)
  double corner_resolution_m = 0.1; // the corner response is computed at this resolution when the map is finer
  double blur_sigma_m = 0.1;
  int corner_block_size = 5;        // gradient window, pixels at the corner resolution
  double harris_k = 0.04;
  double corner_quality = 0.05;     // minimum response relative to the strongest corner of the image
  double corner_spacing_m = 0.4;    // non-maximum suppression distance
  int max_corners = 2000;           // a cap on memory and time in huge maps, far above the usual hundreds
  // Corner arms.
  double arm_search_radius_m = 0.2;
  double min_arm_length_m = 0.3;
  double arm_merge_angle_deg = 15.0;
};

// Cell coordinates (see Alignment): cell (i, j) has its centre at (i, j).
struct LineSegment {
  Eigen::Vector2d a{0.0, 0.0};
  Eigen::Vector2d b{0.0, 0.0};
  double Length() const { return (b - a).norm(); }
  double Angle() const { return std::atan2(b.y() - a.y(), b.x() - a.x()); }
};

struct Corner {
  Eigen::Vector2d position{0.0, 0.0};  // cell coordinates
  double response = 0.0;               // corner response, for ranking (larger is stronger)
  int arms = 0;                        // 2: two walls found; 1: one wall, phi2 is its perpendicular
  double phi1 = 0.0;                   // directed wall directions leaving the corner, radians in (-pi, pi]
  double phi2 = 0.0;
};

struct MapFeatures {
  std::vector<LineSegment> lines;
  std::vector<Corner> corners;  // corners with at least one arm, strongest first (ties by position)
};

// Features of the occupied cells of 'raster'; 'resolution' (metres per cell) converts the metric
// options to cells.
MapFeatures ExtractFeatures(const CellRaster& raster, double resolution, const FeatureOptions& options = {});

}  // namespace pslam
