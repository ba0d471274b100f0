// Fixed-radius neighbour queries of the spatial hash grid, against brute force.
#include <algorithm>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Core>

#include "geometry/spatial_hash_grid.h"

namespace msm_sim::core {
namespace {

// The indices ForEachWithin visits, sorted; fails the test if a visited point is not the one
// inserted under its index.
std::vector<int> Visited(const SpatialHashGrid& grid, const std::vector<Eigen::Vector3d>& points,
                         const Eigen::Vector3d& query, double radius) {
  std::vector<int> visited;
  grid.ForEachWithin(query, radius, [&](int index, const Eigen::Vector3d& point) {
    EXPECT_EQ(point, points.at(index)) << "index " << index;
    visited.push_back(index);
  });
  std::sort(visited.begin(), visited.end());
  return visited;
}

// The indices of the points strictly closer than radius to query, by checking every point.
std::vector<int> BruteForce(const std::vector<Eigen::Vector3d>& points,
                            const Eigen::Vector3d& query, double radius) {
  std::vector<int> within;
  for (int i = 0; i < static_cast<int>(points.size()); ++i) {
    if ((points[i] - query).norm() < radius) within.push_back(i);
  }
  return within;
}

SpatialHashGrid GridOf(const std::vector<Eigen::Vector3d>& points, double cell_size) {
  SpatialHashGrid grid(cell_size);
  for (int i = 0; i < static_cast<int>(points.size()); ++i) grid.Insert(i, points[i]);
  return grid;
}

TEST(SpatialHashGrid, FindsExactlyThePointsWithinTheRadius) {
  std::mt19937_64 random(20240611);
  // A cloud straddling the origin, so that cells of negative index are used too.
  std::uniform_real_distribution<double> coordinate(-2.0, 2.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 3000; ++i) {
    points.emplace_back(coordinate(random), coordinate(random), coordinate(random));
  }
  const double cell_size = 0.5;
  const SpatialHashGrid grid = GridOf(points, cell_size);
  std::uniform_real_distribution<double> query_coordinate(-2.5, 2.5);
  int found = 0;
  for (int q = 0; q < 300; ++q) {
    const Eigen::Vector3d query(query_coordinate(random), query_coordinate(random),
                                query_coordinate(random));
    for (const double radius : {cell_size, 0.3, 0.05}) {
      const std::vector<int> expected = BruteForce(points, query, radius);
      EXPECT_EQ(Visited(grid, points, query, radius), expected)
          << "query " << query.transpose() << " radius " << radius;
      EXPECT_EQ(grid.AnyWithin(query, radius), !expected.empty());
      found += static_cast<int>(expected.size());
    }
  }
  // The comparison must not be vacuous: the full-cell radius finds ~12 points per query.
  EXPECT_GT(found, 1000);
}

TEST(SpatialHashGrid, SearchesTheNeighbouringCells) {
  const double cell_size = 1.0;
  // A query near a cell corner at the origin; points just across each face, edge and corner of
  // its cell, in cells of negative and positive index.
  const Eigen::Vector3d query(0.02, 0.03, -0.01);
  std::vector<Eigen::Vector3d> points = {
      {-0.01, 0.03, -0.01},  // across x = 0
      {0.02, -0.02, -0.01},  // across y = 0
      {0.02, 0.03, 0.01},    // across z = 0
      {-0.01, -0.01, 0.01},  // the diagonally opposite cell
      {0.9, 0.9, -0.9},      // same cell, far away
      {-0.99, 0.03, -0.01},  // next cell, 1.01 away
  };
  const SpatialHashGrid grid = GridOf(points, cell_size);
  EXPECT_EQ(Visited(grid, points, query, 0.1), (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(Visited(grid, points, query, 1.0), BruteForce(points, query, 1.0));
  EXPECT_EQ(Visited(grid, points, query, 1.0).size(), 4u);
}

TEST(SpatialHashGrid, RadiusIsStrict) {
  SpatialHashGrid grid(1.0);
  const std::vector<Eigen::Vector3d> points = {{0.25, 0.0, 0.0}};
  grid.Insert(0, points[0]);
  EXPECT_TRUE(Visited(grid, points, Eigen::Vector3d::Zero(), 0.25).empty());
  EXPECT_FALSE(grid.AnyWithin(Eigen::Vector3d::Zero(), 0.25));
  EXPECT_EQ(Visited(grid, points, Eigen::Vector3d::Zero(), 0.2500001), std::vector<int>{0});
  EXPECT_TRUE(grid.AnyWithin(Eigen::Vector3d::Zero(), 0.2500001));
}

TEST(SpatialHashGrid, FarFromTheOriginAndNegative) {
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> offset(-0.3, 0.3);
  const Eigen::Vector3d centre(-1234.56, 987.65, -4321.0);
  std::vector<Eigen::Vector3d> points;
  for (int i = 0; i < 500; ++i) {
    points.push_back(centre + Eigen::Vector3d(offset(random), offset(random), offset(random)));
  }
  const double cell_size = 0.1;
  const SpatialHashGrid grid = GridOf(points, cell_size);
  for (int q = 0; q < 50; ++q) {
    const Eigen::Vector3d query =
        centre + Eigen::Vector3d(offset(random), offset(random), offset(random));
    EXPECT_EQ(Visited(grid, points, query, cell_size), BruteForce(points, query, cell_size));
  }
  // The same offsets about the mirrored centre are other cells: nothing there.
  EXPECT_FALSE(grid.AnyWithin(-centre, cell_size));
}

TEST(SpatialHashGrid, EmptyGridVisitsNothing) {
  const SpatialHashGrid grid(0.5);
  int visits = 0;
  grid.ForEachWithin(Eigen::Vector3d::Zero(), 0.5, [&](int, const Eigen::Vector3d&) { ++visits; });
  EXPECT_EQ(visits, 0);
  EXPECT_FALSE(grid.AnyWithin(Eigen::Vector3d(1, -2, 3), 0.5));
}

TEST(SpatialHashGrid, RejectsNonPositiveCellSize) {
  EXPECT_THROW(SpatialHashGrid(0.0), std::invalid_argument);
  EXPECT_THROW(SpatialHashGrid(-1.0), std::invalid_argument);
}

}  // namespace
}  // namespace msm_sim::core
