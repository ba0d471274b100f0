#include "msm_sim/lattice/random_lattice_builder.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "geometry/spatial_hash_grid.h"
#include "lattice/lattice_geometry.h"
#include "msm_sim/material/extended_msm.h"
#include "msm_sim/model/model_builder.h"

namespace msm_sim::core {
namespace {

void Validate(const RandomLatticeOptions& options) {
  lattice::ValidateSizeAndSpacing(options.size, options.lattice.spacing);
  if (!(options.min_distance > 0.0) || !(options.max_distance > options.min_distance) ||
      !std::isfinite(options.max_distance)) {
    throw std::invalid_argument("need 0 < min distance < max distance (multiples of l), got " +
                                std::to_string(options.min_distance) + " and " +
                                std::to_string(options.max_distance));
  }
}

struct StarSpring {
  SpringIndex spring;
  Eigen::Vector3d direction;  // unit, pointing away from the node
  double k_l2;                // k L0^2
};

// The eMSM disperses a node's momentum inflow as a pressure, and its inflow measures a volume
// change only, if the node's star weighted by v k L0^2 is isotropic: sum v k L0^2 u u^T ∝ I.
// Random stars are not, and the anisotropy leaks q times into the shear response: harmless for
// q < 0 (|q| < 1/2), but for nu -> 1/2 q grows without bound and E comes out high with v = 1
// (docs/physics.md §3, refinement 3). So for q > 0 choose the least-norm v = 1 + d that makes the
// star isotropic while keeping sum v k L0^2 (6 linear conditions). Stars with fewer than 7 springs,
// or that would need a weight below 0.2, keep v = 1.
void SetIsotropicDispersionWeights(NodeIndex node, const std::vector<StarSpring>& star,
                                   ModelBuilder* builder) {
  const int b = static_cast<int>(star.size());
  if (b < 7) return;
  Eigen::MatrixXd a(6, b);
  for (int n = 0; n < b; ++n) {
    const Eigen::Vector3d& u = star[n].direction;
    a.col(n) << u.x() * u.x() - u.z() * u.z(), u.y() * u.y() - u.z() * u.z(), u.x() * u.y(),
        u.x() * u.z(), u.y() * u.z(), 1.0;
    a.col(n) *= star[n].k_l2;
  }
  Eigen::VectorXd target = -a.rowwise().sum();
  target[5] = 0.0;  // keep sum v k L0^2
  const Eigen::VectorXd d = a.transpose() * (a * a.transpose()).ldlt().solve(target);
  if (!d.allFinite() || d.minCoeff() < -0.8) return;
  for (int n = 0; n < b; ++n) builder->SetDispersionWeight(star[n].spring, node, 1.0 + d[n]);
}

// Where random sequential addition may place nodes and springs.
struct Region {
  Eigen::Vector3d min, max;  // bounding box to draw from
  double volume;             // m^3
  std::function<bool(const Eigen::Vector3d&)> contains;
  // Springs whose segment leaves the body (across a concave notch) would join parts that do
  // not touch; the region can veto them.
  std::function<bool(const Eigen::Vector3d&, const Eigen::Vector3d&)> spring_allowed;
};

// round(V / l^3) nodes, at least one. Throws std::invalid_argument past options.lattice.max_nodes.
int TargetNodeCount(double volume, const RandomLatticeOptions& options) {
  const double l = options.lattice.spacing;
  const double requested = std::round(volume / (l * l * l));
  if (requested > options.lattice.max_nodes) {
    throw std::invalid_argument("the random lattice would have " + std::to_string(requested) +
                                " nodes, more than " + std::to_string(options.lattice.max_nodes) +
                                "; use a larger spacing");
  }
  return std::max(1, static_cast<int>(requested));
}

// Random sequential addition of `target` points at least minL apart inside the region, with a
// spatial hash for the rejection test. Throws std::runtime_error if the draws run out first.
std::vector<Eigen::Vector3d> PlaceNodes(const RandomLatticeOptions& options, const Region& region,
                                        int target) {
  const double min_length = options.min_distance * options.lattice.spacing;
  std::mt19937_64 rng(options.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SpatialHashGrid placed_grid(min_length);
  std::vector<Eigen::Vector3d> points;
  points.reserve(target);
  const long long max_draws = static_cast<long long>(options.max_draws_per_node) * target;
  for (long long draw = 0; draw < max_draws && static_cast<int>(points.size()) < target; ++draw) {
    const Eigen::Vector3d extent = region.max - region.min;
    const Eigen::Vector3d p =
        region.min +
        Eigen::Vector3d(unit(rng) * extent.x(), unit(rng) * extent.y(), unit(rng) * extent.z());
    if (placed_grid.AnyWithin(p, min_length) || !region.contains(p)) continue;
    placed_grid.Insert(static_cast<int>(points.size()), p);
    points.push_back(p);
  }
  if (static_cast<int>(points.size()) < target) {
    throw std::runtime_error("random sequential addition placed only " +
                             std::to_string(points.size()) + " of " + std::to_string(target) +
                             " nodes at min distance " + std::to_string(options.min_distance) +
                             " l; lower the min distance");
  }
  return points;
}

// Two nodes i < j that get a spring, and their distance.
struct NodePair {
  int i, j;
  double length;
};

// Every pair of points closer than max_length whose spring the region allows, in order of i.
// Throws std::invalid_argument if there is none.
std::vector<NodePair> SpringPairs(const std::vector<Eigen::Vector3d>& points, const Region& region,
                                  double max_length) {
  const int num_points = static_cast<int>(points.size());
  std::vector<NodePair> pairs;
  SpatialHashGrid connect_grid(max_length);
  for (int i = 0; i < num_points; ++i) connect_grid.Insert(i, points[i]);
  for (int i = 0; i < num_points; ++i) {
    connect_grid.ForEachWithin(points[i], max_length, [&](int j, const Eigen::Vector3d& q) {
      if (j > i && region.spring_allowed(points[i], q)) {
        pairs.push_back(NodePair{i, j, (q - points[i]).norm()});
      }
    });
  }
  if (pairs.empty()) {
    throw std::invalid_argument("no two nodes are closer than max distance; raise --max-dist");
  }
  return pairs;
}

// The stiffness scale c of the calibration (docs/physics.md §2-3): sum k_i L_i^2 = 15 V mu. With
// k_i = c / L_i^2 every spring contributes c, with uniform k_i = c every spring contributes
// c L_i^2.
double StiffnessScale(const Material& material, double volume, const std::vector<NodePair>& pairs,
                      bool inverse_square) {
  double sum_shape = 0.0;
  for (const NodePair& pair : pairs) {
    sum_shape += inverse_square ? 1.0 : pair.length * pair.length;
  }
  return DirectSpringSumKL2(material, volume) / sum_shape;
}

// Adds the calibrated spring of every pair (times the self-calibration's stiffness factor) and,
// if isotropise, the dispersion weights that make each node's star isotropic
// (SetIsotropicDispersionWeights).
void AddCalibratedSprings(const Material& material, double volume,
                          const RandomLatticeOptions& options, double stiffness_factor,
                          bool isotropise, const std::vector<Eigen::Vector3d>& points,
                          const std::vector<NodePair>& pairs, ModelBuilder* builder) {
  const bool inverse_square = options.stiffness_law == RandomStiffnessLaw::kInverseSquare;
  const double c = stiffness_factor * StiffnessScale(material, volume, pairs, inverse_square);
  std::vector<std::vector<StarSpring>> stars(isotropise ? points.size() : 0);
  for (const NodePair& pair : pairs) {
    const double k = inverse_square ? c / (pair.length * pair.length) : c;
    const SpringIndex s = builder->AddSpring(pair.i, pair.j, k);
    if (!isotropise) continue;
    const Eigen::Vector3d u = (points[pair.j] - points[pair.i]) / pair.length;
    const double k_l2 = k * pair.length * pair.length;
    stars[pair.i].push_back({s, u, k_l2});
    stars[pair.j].push_back({s, -u, k_l2});
  }
  for (std::size_t i = 0; i < stars.size(); ++i) {
    SetIsotropicDispersionWeights(static_cast<NodeIndex>(i), stars[i], builder);
  }
}

Model BuildInRegion(const Material& material, const RandomLatticeOptions& options,
                    const Region& region) {
  const double volume = region.volume;
  const int target = TargetNodeCount(volume, options);
  const std::vector<Eigen::Vector3d> points = PlaceNodes(options, region, target);

  const double node_mass = material.density() * volume / target;
  // The correction in force: a given one, a measured one, or none.
  RandomSelfCalibration calibration{1.0, DispersionFraction(material.poisson_ratio())};
  if (options.calibration) {
    calibration = *options.calibration;
  } else if (options.self_calibrate) {
    calibration = MeasureRandomSelfCalibration(material, options);
  }
  const double q = calibration.dispersion_fraction;
  ModelBuilder builder(material);
  builder.SetSpringLaw(options.lattice.spring_law, options.lattice.power_law);
  builder.SetDispersionFraction(q);
  // A measured correction knows what it was measured for; the model keeps it.
  if (calibration.measurements > 0) builder.SetSelfCalibration(calibration);
  for (const Eigen::Vector3d& p : points) builder.AddNode(p, node_mass);

  const std::vector<NodePair> pairs =
      SpringPairs(points, region, options.max_distance * options.lattice.spacing);
  // Decided by the target, not by the corrected q: near nu = 1/4 a correction that changes the
  // sign of q would otherwise switch the weights and make the measured nu jump.
  const bool isotropise =
      options.isotropic_dispersion && DispersionFraction(material.poisson_ratio()) > 0.0;
  AddCalibratedSprings(material, volume, options, calibration.stiffness_factor, isotropise, points,
                       pairs, &builder);
  return builder.Build(volume, std::cbrt(volume / target));
}

}  // namespace

Model BuildRandomLattice(const Material& material, const RandomLatticeOptions& options) {
  Validate(options);
  Region box{Eigen::Vector3d::Zero(), options.size, options.size.prod(),
             [](const Eigen::Vector3d&) { return true; },
             [](const Eigen::Vector3d&, const Eigen::Vector3d&) { return true; }};
  return BuildInRegion(material, options, box);
}

Model BuildRandomLatticeInSolid(const Material& material, const SolidMesh& solid,
                                const RandomLatticeOptions& options) {
  const Eigen::Vector3d extent = solid.max_corner() - solid.min_corner();
  RandomLatticeOptions checked = options;
  checked.size = extent;
  Validate(checked);
  Region body{solid.min_corner(), solid.max_corner(), solid.volume(),
              [&solid](const Eigen::Vector3d& p) { return solid.Contains(p); },
              [&solid](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
                return !solid.SegmentCrossesSurface(a, b);
              }};
  return BuildInRegion(material, options, body);
}

}  // namespace msm_sim::core
