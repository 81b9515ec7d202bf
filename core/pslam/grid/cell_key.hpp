#pragma once
// A cell index packed into one integer, for hash sets and maps of cells.
#include <Eigen/Core>
#include <cstdint>

namespace pslam {

constexpr std::uint64_t CellKey(int x, int y) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(x)) << 32) | static_cast<std::uint32_t>(y);
}

inline std::uint64_t CellKey(const Eigen::Vector2i& cell) { return CellKey(cell.x(), cell.y()); }

}  // namespace pslam
