#include "pslam/explore/distance_transform.hpp"

#include <cstddef>

namespace pslam {
namespace {

// "Infinity" as in the paper's reference code: a finite value, so that differences of two
// unreachable samples stay finite instead of becoming NaN.
constexpr double kFar = 1e20;

// 1D squared distance transform of the n samples f[0], f[stride], ... in place. v, z, d are
// scratch buffers of at least n, n + 1 and n elements. Doubles, because float loses q^2 next to kFar.
void Transform1D(float* f, int n, std::ptrdiff_t stride, std::vector<int>& v, std::vector<double>& z,
                 std::vector<double>& d) {
  const auto at = [&](int i) { return static_cast<double>(f[i * stride]); };
  // Abscissa where the parabolas rooted at q and p intersect.
  const auto meet = [&](int q, int p) {
    return ((at(q) + static_cast<double>(q) * q) - (at(p) + static_cast<double>(p) * p)) / (2.0 * (q - p));
  };
  std::size_t k = 0;
  v[0] = 0;
  z[0] = -kFar;
  z[1] = kFar;
  for (int q = 1; q < n; ++q) {
    double s = meet(q, v[k]);
    while (s <= z[k]) {  // z[0] = -kFar stops this at k = 0
      --k;
      s = meet(q, v[k]);
    }
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kFar;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q) ++k;
    const double offset = q - v[k];
    d[static_cast<std::size_t>(q)] = offset * offset + at(v[k]);
  }
  for (int q = 0; q < n; ++q) f[q * stride] = static_cast<float>(d[static_cast<std::size_t>(q)]);
}

}  // namespace

std::vector<float> SquaredDistanceTransform(const std::vector<bool>& is_source, int width, int height) {
  std::vector<float> dist(is_source.size());
  for (std::size_t i = 0; i < dist.size(); ++i) dist[i] = is_source[i] ? 0.0f : static_cast<float>(kFar);
  if (width <= 0 || height <= 0) return dist;
  const int longest = width > height ? width : height;
  std::vector<int> v(static_cast<std::size_t>(longest));
  std::vector<double> z(static_cast<std::size_t>(longest) + 1), d(static_cast<std::size_t>(longest));
  for (int x = 0; x < width; ++x) Transform1D(dist.data() + x, height, width, v, z, d);
  for (int y = 0; y < height; ++y) Transform1D(dist.data() + static_cast<std::ptrdiff_t>(y) * width, width, 1, v, z, d);
  return dist;
}

}  // namespace pslam
