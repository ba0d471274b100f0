#include "geometry/spatial_hash_grid.h"

#include <cmath>
#include <stdexcept>

namespace msm_sim::core {

SpatialHashGrid::SpatialHashGrid(double cell_size) : cell_size_(cell_size) {
  if (!(cell_size > 0.0)) throw std::invalid_argument("spatial hash cell size must be > 0");
}

Eigen::Vector3i SpatialHashGrid::CellOf(const Eigen::Vector3d& point) const {
  return (point / cell_size_).array().floor().cast<int>();
}

SpatialHashGrid::CellKey SpatialHashGrid::Key(const Eigen::Vector3i& cell) {
  // 21 bits per axis (offset to be non-negative) covers +-1e6 cells per axis.
  constexpr std::int64_t kOffset = 1 << 20;
  constexpr std::int64_t kMask = (std::int64_t{1} << 21) - 1;
  return ((cell.x() + kOffset) & kMask) | (((cell.y() + kOffset) & kMask) << 21) |
         (((cell.z() + kOffset) & kMask) << 42);
}

void SpatialHashGrid::Insert(int index, const Eigen::Vector3d& point) {
  cells_[Key(CellOf(point))].push_back(Entry{index, point});
}

bool SpatialHashGrid::AnyWithin(const Eigen::Vector3d& query, double radius) const {
  return !Search(query, radius, [](int, const Eigen::Vector3d&) { return false; });
}

}  // namespace msm_sim::core
