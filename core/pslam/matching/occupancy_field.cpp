#include "pslam/matching/occupancy_field.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "pslam/grid/cell_key.hpp"

namespace pslam {
namespace {
struct EvidenceTable {
  std::vector<float> v = std::vector<float>(1 << 16);
  EvidenceTable() {
    for (int c = -32768; c <= 32767; ++c) {
      const float p = CellProbability(static_cast<OccupancyGrid::Cell>(c));
      v[static_cast<std::uint16_t>(c)] = std::max(0.0f, 2.0f * p - 1.0f);
    }
  }
};
}  // namespace

float CellEvidence(OccupancyGrid::Cell c) {
  static const EvidenceTable table;
  return table.v[static_cast<std::uint16_t>(c)];
}

OccupancyField::OccupancyField(const OccupancyGrid& grid, int level)
    : grid_(grid), level_(level), cell_size_(grid.resolution() * (1 << level)) {}

float OccupancyField::Coarse(int i, int j) const {
  if (level_ == 0) return CellEvidence(grid_.At(i, j));
  // A match reads the same few hundred pooled cells over and over: remember them.
  const auto [it, inserted] = pooled_.try_emplace(CellKey(i, j), 0.0f);
  if (!inserted) return it->second;
  const int n = 1 << level_;
  float best = 0.0f;
  for (int y = j * n; y < (j + 1) * n; ++y) {
    for (int x = i * n; x < (i + 1) * n; ++x) best = std::max(best, CellEvidence(grid_.At(x, y)));
  }
  it->second = best;
  return best;
}

float OccupancyField::Value(const Eigen::Vector2f& world, Eigen::Vector2f* gradient) const {
  // Sample positions are cell centres: shift by half a cell before splitting into index + fraction.
  const double u = world.x() / cell_size_ - 0.5, v = world.y() / cell_size_ - 0.5;
  const double fu0 = std::floor(u), fv0 = std::floor(v);
  const int i = static_cast<int>(fu0), j = static_cast<int>(fv0);
  const float fu = static_cast<float>(u - fu0), fv = static_cast<float>(v - fv0);
  const float v00 = Coarse(i, j), v10 = Coarse(i + 1, j), v01 = Coarse(i, j + 1), v11 = Coarse(i + 1, j + 1);
  if (gradient) {
    const float inv = static_cast<float>(1.0 / cell_size_);
    gradient->x() = ((1 - fv) * (v10 - v00) + fv * (v11 - v01)) * inv;
    gradient->y() = ((1 - fu) * (v01 - v00) + fu * (v11 - v10)) * inv;
  }
  return (1 - fv) * ((1 - fu) * v00 + fu * v10) + fv * ((1 - fu) * v01 + fu * v11);
}

}  // namespace pslam
