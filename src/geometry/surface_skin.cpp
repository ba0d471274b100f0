#include "msm_sim/geometry/surface_skin.h"

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

#include <Eigen/Dense>

#include "geometry/spatial_hash_grid.h"

namespace msm_sim::core {
namespace {

// Grows the fit radius by this factor at most three times (1.5 -> 2.25 -> 3.4 -> 5.1 cells by
// default) until the neighbours fill a ball well enough to extrapolate a corner from.
constexpr double kRadiusGrowth = 1.5;
constexpr int kRadiusSteps = 4;
// Smallest over largest principal moment of a neighbourhood that is "well spread": a thin cap
// of nodes (the pole of a sphere seen from a corner outside it) is not, and an affine fit to it
// extrapolated far off its plane amplified a bend 10-fold.
constexpr double kMinSpread = 0.05;

struct Neighbour {
  int node;
  Eigen::Vector3d offset;  // rest position - corner
  double weight;
};

// Weights alpha_n with sum alpha_n = 1 and sum alpha_n X_n = corner: the value at the corner of
// the weighted least-squares affine fit through the neighbours. With Xbar the weighted mean and
// M = sum w (X - Xbar)(X - Xbar)^T, alpha_n = w_n / W + w_n (corner - Xbar)^T M^+ (X_n - Xbar).
// M^+ drops directions the neighbours do not span (a one-layer plate): the corner then follows
// them exactly in the plane and rigidly along its normal only to first order.
std::vector<double> AffineFitWeights(const std::vector<Neighbour>& neighbours) {
  double total = 0.0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();  // relative to the corner
  for (const Neighbour& n : neighbours) {
    total += n.weight;
    mean += n.weight * n.offset;
  }
  mean /= total;
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (const Neighbour& n : neighbours) {
    const Eigen::Vector3d r = n.offset - mean;
    moment += n.weight * r * r.transpose();
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(moment);
  const double largest = eigen.eigenvalues().maxCoeff();
  Eigen::Vector3d inverse_values = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i) {
    if (eigen.eigenvalues()[i] > 1e-9 * largest) inverse_values[i] = 1.0 / eigen.eigenvalues()[i];
  }
  const Eigen::Matrix3d pseudo_inverse =
      eigen.eigenvectors() * inverse_values.asDiagonal() * eigen.eigenvectors().transpose();
  const Eigen::Vector3d g = pseudo_inverse * (-mean);  // M^+ (corner - Xbar), corner = 0
  std::vector<double> alpha;
  alpha.reserve(neighbours.size());
  for (const Neighbour& n : neighbours) {
    alpha.push_back(n.weight / total + n.weight * g.dot(n.offset - mean));
  }
  return alpha;
}

bool SpansSpace(const std::vector<Neighbour>& neighbours) {
  if (neighbours.size() < 4) return false;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Neighbour& n : neighbours) mean += n.offset;
  mean /= static_cast<double>(neighbours.size());
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
  for (const Neighbour& n : neighbours) moment += (n.offset - mean) * (n.offset - mean).transpose();
  const Eigen::Vector3d values =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(moment).eigenvalues();
  return values.minCoeff() > kMinSpread * values.maxCoeff();
}

std::uint64_t CornerKey(const Eigen::Vector3i& c) {
  return (static_cast<std::uint64_t>(c.x() & 0x1FFFFF) << 42) |
         (static_cast<std::uint64_t>(c.y() & 0x1FFFFF) << 21) |
         static_cast<std::uint64_t>(c.z() & 0x1FFFFF);
}

// Throws std::invalid_argument as SurfaceSkin::Embed documents, except for corners far from
// the nodes (found later).
void CheckEmbedInput(const Model& model, const TriangleMesh& surface,
                     const SurfaceSkinOptions& options) {
  if (model.num_nodes() < 4) throw std::invalid_argument("skinning needs a model of >= 4 nodes");
  if (surface.num_triangles() == 0) throw std::invalid_argument("the skin mesh has no triangles");
  if (!surface.vertices.allFinite()) {
    throw std::invalid_argument("the skin mesh has non-finite vertex coordinates");
  }
  if (!std::isfinite(options.cell_size) || !(options.fit_radius > 0.0) ||
      !std::isfinite(options.fit_radius)) {
    throw std::invalid_argument("skin cell size and fit radius must be finite, fit radius > 0");
  }
}

// The nodes within fit_radius * h of `position`, weighted, in the smallest of the growing balls
// where they span space (or the largest ball if none does).
std::vector<Neighbour> FitNeighbours(const SpatialHashGrid& grid, const Eigen::Vector3d& position,
                                     double fit_radius, double h) {
  std::vector<Neighbour> neighbours;
  for (int step = 0; step < kRadiusSteps; ++step) {
    const double radius = fit_radius * h * std::pow(kRadiusGrowth, step);
    neighbours.clear();
    grid.ForEachWithin(position, radius, [&](int node, const Eigen::Vector3d& p) {
      const double s = (p - position).squaredNorm() / (radius * radius);
      // Smooth compact weight: neighbours entering or leaving the ball do not jump.
      neighbours.push_back({node, p - position, (1.0 - s) * (1.0 - s)});
    });
    if (SpansSpace(neighbours)) break;
  }
  return neighbours;
}

// Appends to *triplets row `corner` of the corner weights: the affine fit of the nodes around
// the corner's `position`. Throws std::invalid_argument naming skin vertex `vertex` if fewer than
// 4 nodes lie within max_radius of it.
void AppendCornerWeights(const SpatialHashGrid& grid, const Eigen::Vector3d& position,
                         const SurfaceSkinOptions& options, double h, double max_radius, int vertex,
                         int corner, std::vector<Eigen::Triplet<double>>* triplets) {
  const std::vector<Neighbour> neighbours = FitNeighbours(grid, position, options.fit_radius, h);
  if (neighbours.size() < 4) {
    throw std::invalid_argument(
        "skin vertex " + std::to_string(vertex) + " is more than " + std::to_string(max_radius) +
        " m from the model's nodes; is the mesh in the model's frame and scale?");
  }
  const std::vector<double> alpha = AffineFitWeights(neighbours);
  for (std::size_t n = 0; n < neighbours.size(); ++n) {
    triplets->emplace_back(corner, neighbours[n].node, alpha[n]);
  }
}

}  // namespace

std::array<double, 8> TrilinearWeights(const Eigen::Vector3d& u) {
  std::array<double, 8> w;
  for (int corner = 0; corner < 8; ++corner) {
    w[corner] = (corner & 1 ? u.x() : 1.0 - u.x()) * (corner & 2 ? u.y() : 1.0 - u.y()) *
                (corner & 4 ? u.z() : 1.0 - u.z());
  }
  return w;
}

SurfaceSkin SurfaceSkin::Embed(const Model& model, const TriangleMesh& surface,
                               const SurfaceSkinOptions& options) {
  CheckEmbedInput(model, surface, options);
  const double h =
      options.cell_size > 0.0 ? options.cell_size : 0.5 * model.characteristic_length();
  const double max_radius = options.fit_radius * h * std::pow(kRadiusGrowth, kRadiusSteps - 1);
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  SpatialHashGrid grid(max_radius);
  for (int i = 0; i < model.num_nodes(); ++i) grid.Insert(i, rest.col(i));

  SurfaceSkin skin;
  skin.surface_ = surface;
  const int num_vertices = surface.num_vertices();
  skin.host_corners_.resize(num_vertices);
  skin.cell_coordinates_.resize(3, num_vertices);
  std::unordered_map<std::uint64_t, int> corner_index;
  std::vector<Eigen::Triplet<double>> triplets;
  int num_corners = 0;
  // The grid's origin is the surface's smallest corner, so no vertex sits on a cell face by
  // accident of coordinates (it would still be fine: coordinates in [0, 1] either side).
  const Eigen::Vector3d origin = surface.vertices.rowwise().minCoeff();
  for (int v = 0; v < num_vertices; ++v) {
    const Eigen::Vector3d g = (surface.vertices.col(v) - origin) / h;
    const Eigen::Vector3i cell = g.array().floor().cast<int>();
    skin.cell_coordinates_.col(v) = (g - cell.cast<double>()).cwiseMax(0.0).cwiseMin(1.0);
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3i c = cell + Eigen::Vector3i(corner & 1, (corner >> 1) & 1, corner >> 2);
      const auto [it, inserted] = corner_index.emplace(CornerKey(c), num_corners);
      skin.host_corners_[v][corner] = it->second;
      if (!inserted) continue;
      ++num_corners;
      AppendCornerWeights(grid, origin + h * c.cast<double>(), options, h, max_radius, v,
                          it->second, &triplets);
    }
  }
  skin.corner_weights_.resize(num_corners, model.num_nodes());
  skin.corner_weights_.setFromTriplets(triplets.begin(), triplets.end());
  return skin;
}

Eigen::Matrix3Xd SurfaceSkin::CornerPositions(const Eigen::Matrix3Xd& node_positions) const {
  if (node_positions.cols() != corner_weights_.cols()) {
    throw std::invalid_argument("skin: expected " + std::to_string(corner_weights_.cols()) +
                                " node positions, got " + std::to_string(node_positions.cols()));
  }
  // Every row of weights sums to 1, so the corners can be computed from positions relative to
  // their mean: the weights (large where a corner is extrapolated) then do not multiply the
  // rounding of a large translation.
  const Eigen::Vector3d mean = node_positions.rowwise().mean();
  const Eigen::Matrix3Xd relative = node_positions.colwise() - mean;
  return ((corner_weights_ * relative.transpose()).transpose()).colwise() + mean;
}

Eigen::Matrix3Xd SurfaceSkin::DeformedVertices(const Eigen::Matrix3Xd& node_positions) const {
  const Eigen::Matrix3Xd corners = CornerPositions(node_positions);
  Eigen::Matrix3Xd vertices(3, num_vertices());
  for (int v = 0; v < num_vertices(); ++v) {
    const std::array<double, 8> w = TrilinearWeights(cell_coordinates_.col(v));
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int corner = 0; corner < 8; ++corner)
      p += w[corner] * corners.col(host_corners_[v][corner]);
    vertices.col(v) = p;
  }
  return vertices;
}

Eigen::Matrix3Xd SurfaceSkin::DeformedNormals(const Eigen::Matrix3Xd& deformed_vertices) const {
  return VertexNormals(surface_, deformed_vertices);
}

}  // namespace msm_sim::core
