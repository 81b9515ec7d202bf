#pragma once
// Exact Euclidean distance transform of a binary image (Felzenszwalb & Huttenlocher, "Distance
// transforms of sampled functions", 2012): two passes of the 1D lower-envelope-of-parabolas
// algorithm, linear in the number of cells. Used to inflate obstacles by the robot radius.
#include <vector>

namespace pslam {

// For a width x height row-major image where 'is_source' marks the sources (obstacles), returns
// for every cell the squared distance in cells to the nearest source; a large value (>= 1e20)
// when there is no source at all.
std::vector<float> SquaredDistanceTransform(const std::vector<bool>& is_source, int width, int height);

}  // namespace pslam
