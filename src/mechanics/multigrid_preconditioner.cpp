// The implicit step's multigrid V-cycle (multigrid_preconditioner.h, docs/physics.md §7.1).

#include "mechanics/multigrid_preconditioner.h"

#include "msm_sim/mechanics/force_evaluator.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <stdexcept>
#include <utility>

namespace msm_sim::core::internal {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

// Chebyshev smoothing works on [largest / kSmoothedRange, largest] of diag(A)^-1 A: the part of
// the spectrum the coarse levels do not reach.
constexpr double kSmoothedRange = 30.0;
// The estimated largest eigenvalue is raised by this much: an underestimate would let the
// polynomial amplify the highest modes and the V-cycle lose its positivity.
constexpr double kEigenvalueMargin = 1.1;
constexpr int kPowerIterations = 15;
// A coordinate this close to a coarse grid line (in coarse spacings) lies on it: its node takes
// the line's vertices only, so a cubic lattice's nodes on even grid lines need no others.
constexpr double kOnGridLine = 1e-9;

// Trilinear interpolation from a grid of spacing `spacing` through `origin` to `points`: the
// scalar prolongation (points x vertices) and the vertices' positions.
SparseMatrix TrilinearProlongation(const Eigen::Matrix3Xd& points, const Eigen::Vector3d& origin,
                                   double spacing, Eigen::Matrix3Xd* vertices) {
  std::map<std::array<long, 3>, int> vertex_of;
  std::vector<Eigen::Triplet<double>> weights;
  std::vector<Eigen::Vector3d> positions;
  for (Eigen::Index p = 0; p < points.cols(); ++p) {
    std::array<long, 3> cell{};
    Eigen::Vector3d t;
    for (int d = 0; d < 3; ++d) {
      const double u = (points(d, p) - origin[d]) / spacing;
      cell[d] = static_cast<long>(std::floor(u + kOnGridLine));
      t[d] = std::max(0.0, u - static_cast<double>(cell[d]));
      if (t[d] < kOnGridLine) t[d] = 0.0;
    }
    for (int corner = 0; corner < 8; ++corner) {
      double weight = 1.0;
      std::array<long, 3> vertex = cell;
      for (int d = 0; d < 3; ++d) {
        const bool upper = (corner >> d) & 1;
        weight *= upper ? t[d] : 1.0 - t[d];
        vertex[d] += upper ? 1 : 0;
      }
      if (weight == 0.0) continue;
      const auto [slot, added] = vertex_of.emplace(vertex, static_cast<int>(positions.size()));
      if (added) {
        positions.push_back(origin + spacing * Eigen::Vector3d(static_cast<double>(vertex[0]),
                                                               static_cast<double>(vertex[1]),
                                                               static_cast<double>(vertex[2])));
      }
      weights.emplace_back(static_cast<int>(p), slot->second, weight);
    }
  }
  vertices->resize(3, static_cast<Eigen::Index>(positions.size()));
  for (std::size_t v = 0; v < positions.size(); ++v) {
    vertices->col(static_cast<Eigen::Index>(v)) = positions[v];
  }
  SparseMatrix prolongation(points.cols(), static_cast<Eigen::Index>(positions.size()));
  prolongation.setFromTriplets(weights.begin(), weights.end());
  return prolongation;
}

// The prolongation with the rows of held nodes zero (a coarse correction never moves them, and
// the coarse operators then see them clamped, as the solve does) and without the vertices left
// with no node; *vertices keeps the remaining ones.
SparseMatrix WithoutHeldNodes(const std::vector<char>& held, const SparseMatrix& prolongation,
                              Eigen::Matrix3Xd* vertices) {
  std::vector<int> kept(static_cast<std::size_t>(prolongation.cols()), -1);
  int count = 0;
  for (Eigen::Index column = 0; column < prolongation.outerSize(); ++column) {
    for (SparseMatrix::InnerIterator it(prolongation, column); it; ++it) {
      if (!held[static_cast<std::size_t>(it.row())]) {
        kept[static_cast<std::size_t>(column)] = count++;
        break;
      }
    }
  }
  std::vector<Eigen::Triplet<double>> weights;
  Eigen::Matrix3Xd remaining(3, count);
  for (Eigen::Index column = 0; column < prolongation.outerSize(); ++column) {
    const int slot = kept[static_cast<std::size_t>(column)];
    if (slot < 0) continue;
    remaining.col(slot) = vertices->col(column);
    for (SparseMatrix::InnerIterator it(prolongation, column); it; ++it) {
      if (!held[static_cast<std::size_t>(it.row())]) {
        weights.emplace_back(static_cast<int>(it.row()), slot, it.value());
      }
    }
  }
  *vertices = std::move(remaining);
  SparseMatrix without(prolongation.rows(), count);
  without.setFromTriplets(weights.begin(), weights.end());
  return without;
}

// The scalar prolongation applied to each of x, y and z (DOF 3 i + d).
SparseMatrix PerAxis(const SparseMatrix& scalar) {
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(3 * static_cast<std::size_t>(scalar.nonZeros()));
  for (Eigen::Index column = 0; column < scalar.outerSize(); ++column) {
    for (SparseMatrix::InnerIterator it(scalar, column); it; ++it) {
      for (int d = 0; d < 3; ++d) {
        entries.emplace_back(3 * it.row() + d, 3 * it.col() + d, it.value());
      }
    }
  }
  SparseMatrix vector_prolongation(3 * scalar.rows(), 3 * scalar.cols());
  vector_prolongation.setFromTriplets(entries.begin(), entries.end());
  return vector_prolongation;
}

// x += the Chebyshev smoothing of degree `degree` of A x = b, with product(v) = A v and
// scale(r) = diag(A)^-1 r (both in the caller's subspace). A zero x saves the first product.
template <typename Vector, typename Product, typename Scale>
void ChebyshevSmooth(const Product& product, const Scale& scale, double largest, int degree,
                     const Vector& b, bool x_is_zero, Vector* x) {
  if (!(largest > 0.0)) return;  // nothing left to smooth (every DOF held)
  const double upper = largest;
  const double lower = upper / kSmoothedRange;
  const double centre = 0.5 * (upper + lower);
  const double half_width = 0.5 * (upper - lower);
  const double sigma = centre / half_width;
  double rho = 1.0 / sigma;
  Vector r = x_is_zero ? b : Vector(b - product(*x));
  Vector d = scale(r) / centre;
  for (int k = 0; k < degree; ++k) {
    *x += d;
    if (k + 1 == degree) break;
    r -= product(d);
    const double rho_next = 1.0 / (2.0 * sigma - rho);
    d = (rho_next * rho) * d + (2.0 * rho_next / half_width) * scale(r);
    rho = rho_next;
  }
}

// The largest eigenvalue of diag(A)^-1 A by power iteration from a seeded start, with the margin.
template <typename Vector, typename Product, typename Scale>
double LargestEigenvalue(const Product& product, const Scale& scale, Vector start) {
  double estimate = 0.0;
  for (int it = 0; it < kPowerIterations; ++it) {
    const double norm = start.norm();
    if (!(norm > 0.0)) break;
    start /= norm;
    Vector next = scale(product(start));
    estimate = next.norm();
    start = std::move(next);
  }
  return kEigenvalueMargin * estimate;
}

// A coarse level's system product and its diagonal scaling, for the smoother and the eigenvalue
// estimate.
struct LevelProduct {
  const MultigridLevel& level;
  Eigen::VectorXd operator()(const Eigen::VectorXd& v) const { return level.system * v; }
};
struct LevelScale {
  const MultigridLevel& level;
  Eigen::VectorXd operator()(const Eigen::VectorXd& r) const {
    return level.inverse_diagonal.cwiseProduct(r);
  }
};

Eigen::VectorXd SeededStart(Eigen::Index size) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd start(size);
  for (Eigen::Index i = 0; i < size; ++i) start[i] = uniform(rng);
  return start;
}

}  // namespace

MultigridPreconditioner::MultigridPreconditioner(const Model& model,
                                                 const SparseMatrix& rest_stiffness,
                                                 const std::vector<char>& held,
                                                 const MultigridOptions& options)
    : options_(options), held_(held) {
  if (options.smoothing_degree < 1 || options.coarsest_nodes < 1) {
    throw std::invalid_argument("multigrid: smoothing degree and coarsest nodes must be >= 1");
  }
  const Eigen::Matrix3Xd& rest = model.rest_positions();
  const Eigen::Vector3d origin = rest.rowwise().minCoeff();
  Eigen::VectorXd masses(3 * model.num_nodes());
  for (int i = 0; i < model.num_nodes(); ++i)
    masses.segment<3>(3 * i).setConstant(model.masses()[i]);
  SparseMatrix mass(masses.asDiagonal());
  SparseMatrix stiffness = rest_stiffness;
  Eigen::Matrix3Xd points = rest;
  double spacing = 2.0 * model.characteristic_length();
  while (points.cols() > options.coarsest_nodes) {
    Eigen::Matrix3Xd vertices;
    SparseMatrix prolongation = TrilinearProlongation(points, origin, spacing, &vertices);
    if (levels_.empty() && !held.empty())
      prolongation = WithoutHeldNodes(held, prolongation, &vertices);
    prolongation = PerAxis(prolongation);
    // A grid that no longer thins the nodes out (a body one cell thick) ends the hierarchy.
    if (vertices.cols() * 4 > points.cols() * 3) break;
    MultigridLevel level;
    level.vertices = vertices;
    level.prolongation = prolongation;
    const SparseMatrix restriction = prolongation.transpose();
    level.mass = restriction * mass * prolongation;
    level.stiffness = restriction * stiffness * prolongation;
    mass = level.mass;
    stiffness = level.stiffness;
    levels_.push_back(std::move(level));
    points = std::move(vertices);
    spacing *= 2.0;
  }
}

std::shared_ptr<MultigridPreconditioner> MultigridPreconditioner::ForRestState(
    const Model& model, const std::vector<char>& held) {
  ForceEvaluator rest(model, DispersionPasses::kTwoPass, SpringKernels::kPerSpring);
  rest.Linearize(model.rest_positions(), GeometricStiffness::kDropCompression);
  return std::make_shared<MultigridPreconditioner>(model, rest.StiffnessMatrix(), held);
}

void MultigridPreconditioner::SetStepFactor(double c) {
  if (c == step_factor_) return;
  step_factor_ = c;
  fine_largest_eigenvalue_ = 0.0;
  for (std::size_t l = 0; l < levels_.size(); ++l) {
    MultigridLevel& level = levels_[l];
    level.system = level.mass + c * level.stiffness;
    level.inverse_diagonal = level.system.diagonal().cwiseInverse();
    level.largest_eigenvalue =
        LargestEigenvalue(LevelProduct{level}, LevelScale{level}, SeededStart(level.system.rows()));
  }
  if (!levels_.empty()) {
    coarsest_.compute(SparseMatrix(levels_.back().system));
    // Should the coarsest system not factorise, the V-cycle goes without the coarse levels
    // (smoothing alone is still a symmetric positive preconditioner).
    if (coarsest_.info() != Eigen::Success) levels_.clear();
  }
}

void MultigridPreconditioner::CoarseCycle(int l, const Eigen::VectorXd& b,
                                          Eigen::VectorXd* x) const {
  const MultigridLevel& level = levels_[l];
  if (l + 1 == static_cast<int>(levels_.size())) {
    *x = coarsest_.solve(b);
    return;
  }
  const LevelProduct product{level};
  const LevelScale scale{level};
  const MultigridLevel& below = levels_[l + 1];
  x->setZero(b.size());
  ChebyshevSmooth(product, scale, level.largest_eigenvalue, options_.smoothing_degree, b, true, x);
  const Eigen::VectorXd coarse_b = below.prolongation.transpose() * (b - product(*x));
  Eigen::VectorXd correction;
  CoarseCycle(l + 1, coarse_b, &correction);
  *x += below.prolongation * correction;
  ChebyshevSmooth(product, scale, level.largest_eigenvalue, options_.smoothing_degree, b, false, x);
}

void MultigridPreconditioner::Apply(const NodeArrayOperator& apply,
                                    const Eigen::Matrix3Xd& inverse_diagonal,
                                    const DofProjection& projection,
                                    const Eigen::Matrix3d& rotation, const Eigen::Matrix3Xd& r,
                                    Eigen::Matrix3Xd* z) const {
  const auto product = [&](const Eigen::Matrix3Xd& v) -> Eigen::Matrix3Xd {
    Eigen::Matrix3Xd out(3, v.cols());
    apply(v, &out);
    projection.Apply(&out);
    return out;
  };
  const auto scale = [&](const Eigen::Matrix3Xd& residual) -> Eigen::Matrix3Xd {
    Eigen::Matrix3Xd scaled = inverse_diagonal.cwiseProduct(residual);
    projection.Apply(&scaled);
    return scaled;
  };
  if (fine_largest_eigenvalue_ == 0.0) {
    Eigen::Matrix3Xd start =
        Eigen::Map<const Eigen::Matrix3Xd>(SeededStart(r.size()).data(), 3, r.cols());
    projection.Apply(&start);
    fine_largest_eigenvalue_ = LargestEigenvalue(product, scale, start);
  }
  z->setZero(3, r.cols());
  ChebyshevSmooth(product, scale, fine_largest_eigenvalue_, options_.smoothing_degree, r, true, z);
  if (!levels_.empty()) {
    const Eigen::Matrix3Xd residual = rotation.transpose() * (r - product(*z));
    const Eigen::VectorXd coarse_b =
        levels_[0].prolongation.transpose() *
        Eigen::Map<const Eigen::VectorXd>(residual.data(), residual.size());
    Eigen::VectorXd correction;
    CoarseCycle(0, coarse_b, &correction);
    const Eigen::VectorXd fine_correction = levels_[0].prolongation * correction;
    Eigen::Matrix3Xd lifted =
        rotation * Eigen::Map<const Eigen::Matrix3Xd>(fine_correction.data(), 3, r.cols());
    projection.Apply(&lifted);
    *z += lifted;
  }
  ChebyshevSmooth(product, scale, fine_largest_eigenvalue_, options_.smoothing_degree, r, false, z);
}

}  // namespace msm_sim::core::internal
