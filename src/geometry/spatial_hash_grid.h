#pragma once

#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>

namespace msm_sim::core {

/// Uniform-grid spatial hash over points, for fixed-radius neighbour queries.
///
/// Cells are cubes of edge `cell_size`; a query of radius r <= cell_size only inspects the 27
/// cells around the query point. Points are referred to by the index they were inserted with.
class SpatialHashGrid {
 public:
  /// Precondition: cell_size > 0.
  explicit SpatialHashGrid(double cell_size);

  void Insert(int index, const Eigen::Vector3d& point);

  /// Calls visit(index, point) for every inserted point strictly closer than `radius` to `query`.
  /// Precondition: radius <= cell_size.
  template <typename Visitor>
  void ForEachWithin(const Eigen::Vector3d& query, double radius, Visitor&& visit) const {
    Search(query, radius, [&](int index, const Eigen::Vector3d& point) {
      visit(index, point);
      return true;
    });
  }

  /// True if any inserted point lies strictly closer than `radius` to `query`.
  bool AnyWithin(const Eigen::Vector3d& query, double radius) const;

 private:
  using CellKey = std::int64_t;
  struct Entry {
    int index;
    Eigen::Vector3d point;
  };
  Eigen::Vector3i CellOf(const Eigen::Vector3d& point) const;
  static CellKey Key(const Eigen::Vector3i& cell);

  // Visits the points closer than radius in the 27 cells around query until visit returns false;
  // returns false if it was stopped.
  template <typename Visitor>
  bool Search(const Eigen::Vector3d& query, double radius, Visitor&& visit) const;

  double cell_size_;
  std::unordered_map<CellKey, std::vector<Entry>> cells_;
};

template <typename Visitor>
bool SpatialHashGrid::Search(const Eigen::Vector3d& query, double radius, Visitor&& visit) const {
  const Eigen::Vector3i centre = CellOf(query);
  const double radius_sq = radius * radius;
  for (int dx = -1; dx <= 1; ++dx) {
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dz = -1; dz <= 1; ++dz) {
        const auto it = cells_.find(Key(centre + Eigen::Vector3i(dx, dy, dz)));
        if (it == cells_.end()) continue;
        for (const Entry& entry : it->second) {
          if ((entry.point - query).squaredNorm() < radius_sq && !visit(entry.index, entry.point)) {
            return false;
          }
        }
      }
    }
  }
  return true;
}

}  // namespace msm_sim::core
