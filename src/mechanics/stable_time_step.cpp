#include "msm_sim/mechanics/stable_time_step.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "mechanics/node_array_krylov.h"
#include "msm_sim/mechanics/force_evaluator.h"

namespace msm_sim::core {
namespace {

void Validate(const StableTimeStepOptions& options) {
  if (!(options.safety > 0.0 && options.safety <= 1.0) ||
      !(options.min_compression > 0.0 && options.min_compression <= 1.0) ||
      !(options.max_stretch >= 1.0) || !std::isfinite(options.max_stretch) ||
      !(options.damping_beta >= 0.0) || !std::isfinite(options.damping_beta)) {
    throw std::invalid_argument(
        "stable time step: need safety and min_compression in (0, 1], max_stretch finite and "
        ">= 1 and damping >= 0");
  }
}

// 1 for a node that moves, 0 for a fixed one, as a row to scale the 3 x N vectors with.
Eigen::Array<double, 1, Eigen::Dynamic> FreeMask(const Model& model,
                                                 const std::vector<NodeIndex>& fixed_nodes) {
  Eigen::Array<double, 1, Eigen::Dynamic> free =
      Eigen::Array<double, 1, Eigen::Dynamic>::Ones(model.num_nodes());
  for (const NodeIndex node : fixed_nodes) {
    if (node < 0 || node >= model.num_nodes()) {
      throw std::invalid_argument("stable time step: fixed node " + std::to_string(node) +
                                  " is not a node of the model");
    }
    free[node] = 0.0;
  }
  return free;
}

// M^-1/2 B M^-1/2 applied matrix-free for an operator B (K or the dampers' matrix), restricted
// to the free nodes (`free` is 1 for those, 0 for fixed ones: rows and columns dropped); the
// eigenvalues of M^-1/2 K M^-1/2 are the squared angular frequencies.
NodeArrayOperator MassScaled(NodeArrayOperator b, const Eigen::VectorXd& masses,
                             const Eigen::Array<double, 1, Eigen::Dynamic>& free) {
  const Eigen::Array<double, 1, Eigen::Dynamic> inverse_sqrt_mass =
      masses.transpose().array().rsqrt() * free;
  return [b = std::move(b), inverse_sqrt_mass](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    const Eigen::Matrix3Xd scaled = v.array().rowwise() * inverse_sqrt_mass;
    b(scaled, out);
    *out = out->array().rowwise() * inverse_sqrt_mass;
  };
}

// The dampers' matrix C / beta = sum k (e_b - e_a)(e_b - e_a)^T (x) u u^T at rest: a damper
// carries beta k (v_b - v_a).u on the spring's own k, not on the eMSM dispersion or Baudet's
// correction, so at nu > 1/4 C is much softer than K.
NodeArrayOperator DamperMatrix(const Model& model) {
  const int count = model.num_springs();
  Eigen::Matrix3Xd directions(3, count);
  for (int s = 0; s < count; ++s) {
    directions.col(s) = (model.rest_positions().col(model.spring_node_b()[s]) -
                         model.rest_positions().col(model.spring_node_a()[s]))
                            .normalized();
  }
  return [&model, directions](const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd* out) {
    out->setZero(3, v.cols());
    for (int s = 0; s < model.num_springs(); ++s) {
      const NodeIndex a = model.spring_node_a()[s], b = model.spring_node_b()[s];
      const Eigen::Vector3d u = directions.col(s);
      const Eigen::Vector3d f = model.spring_stiffness()[s] * u.dot(v.col(b) - v.col(a)) * u;
      out->col(a) -= f;
      out->col(b) += f;
    }
  };
}

// A deterministic unit start with a component along the highest modes (an alternating pattern).
Eigen::Matrix3Xd AlternatingStart(int n) {
  Eigen::Matrix3Xd v(3, n);
  for (int i = 0; i < n; ++i) {
    v.col(i) = Eigen::Vector3d(i % 2 ? 1.0 : -1.0, (i / 2) % 2 ? 1.0 : -0.7, (i % 3) - 1.1);
  }
  v /= v.norm();
  return v;
}

// Up to `steps` Lanczos vectors from `start` (reorthogonalised twice against all before), the
// next from product(m), the operator applied to basis[m] (the caller may record it). Stops early
// at an invariant subspace, where the basis is exact.
void BuildKrylovBasis(const std::function<Eigen::Matrix3Xd(int)>& product,
                      const Eigen::Matrix3Xd& start, int steps,
                      std::vector<Eigen::Matrix3Xd>* basis) {
  basis->assign(1, start);
  for (int m = 0; m < steps; ++m) {
    Eigen::Matrix3Xd av = product(m);
    if (m + 1 == steps) break;
    const double product_norm = av.norm();
    for (int pass = 0; pass < 2; ++pass) {
      for (const Eigen::Matrix3Xd& q : *basis) av -= (q.array() * av.array()).sum() * q;
    }
    const double norm = av.norm();
    if (norm <= 1e-10 * product_norm) break;  // an invariant subspace: exact
    basis->push_back(av / norm);
  }
}

// The largest eigenvalue of the projection Q^T A Q, formed explicitly from the stored products
// (symmetrised), which keeps it a lower bound of lambda_max whatever rounding does to the
// three-term recurrence.
double LargestRitzValue(const std::vector<Eigen::Matrix3Xd>& basis,
                        const std::vector<Eigen::Matrix3Xd>& products) {
  const int m = static_cast<int>(products.size());
  Eigen::MatrixXd projection(m, m);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < m; ++j) projection(i, j) = (basis[i].array() * products[j].array()).sum();
  }
  projection = 0.5 * (projection + projection.transpose()).eval();
  return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(projection).eigenvalues().maxCoeff();
}

// For symmetric K. Rayleigh-Ritz on a Krylov basis (Lanczos vectors, reorthogonalised twice):
// the largest eigenvalue of Q^T A Q converges to lambda_max in a few dozen products even where
// the top of the spectrum is clustered (a lattice's is, where power iteration falls short;
// docs/physics.md §7 "Stable time step"), and never exceeds it.
double LargestEigenvalueByRayleighRitz(const NodeArrayOperator& stiffness,
                                       const Eigen::Matrix3Xd& start) {
  const int n = static_cast<int>(start.cols());
  const int steps = std::min(60, 3 * n);
  std::vector<Eigen::Matrix3Xd> basis;
  std::vector<Eigen::Matrix3Xd> products;
  Eigen::Matrix3Xd av(3, start.cols());
  BuildKrylovBasis(
      [&](int m) {
        stiffness(basis[m], &av);
        products.push_back(av);
        return av;
      },
      start, steps, &basis);
  return LargestRitzValue(basis, products);
}

// The factor on K's eigenvalues: the largest tangent over k for stretches s in [c, S] (c =
// min_compression, S = max_stretch). Carrier springs: (L0 / L)^2, largest at c. The power law
// (docs/physics.md §4.1): s^(alpha-1) + 3 beta (s-1)^2, each term largest at c or S, so the sum
// of their maxima bounds it (exact for beta = 0).
double Stiffening(const Model& model, const StableTimeStepOptions& options) {
  const double c = options.min_compression, stretch = options.max_stretch;
  switch (model.spring_law()) {
    case SpringLaw::kLinear:
      return 1.0;
    case SpringLaw::kNonlinear:
      return 1.0 / (c * c);
    case SpringLaw::kPower: {
      const PowerSpringLaw& law = model.power_spring_law();
      const double power =
          std::max(std::pow(c, law.alpha - 1.0), std::pow(stretch, law.alpha - 1.0));
      const double far = std::max(1.0 - c, stretch - 1.0);
      return std::max(1.0, power + 3.0 * law.beta * far * far);
    }
  }
  throw std::logic_error("stable time step: unknown spring law");
}

// The position-Verlet limit (without the safety factor) for the largest eigenvalues lambda of
// M^-1/2 K M^-1/2 (already stiffened) and lambda_damper of M^-1/2 (C / beta) M^-1/2 at rest: the
// largest h with (h^2 / 4) lambda + (h / 2) beta lambda_damper <= 1, sufficient (see the header).
double StepForLargestEigenvalues(double lambda, double lambda_damper, double beta) {
  const double a = 0.25 * lambda;
  const double b = 0.5 * beta * lambda_damper;
  // The positive root of a h^2 + b h - 1, written without cancellation.
  return 2.0 / (b + std::sqrt(b * b + 4.0 * a));
}

// The Rayleigh-Ritz projections Q^T (s K) Q and Q^T (beta C) Q (K and C mass-scaled, C without
// beta, s the carrier springs' stiffening) on an orthonormal Krylov (Lanczos) basis Q of up to
// `steps` vectors of the pencil (h^2 / 4) s K + (h / 2) beta C, each formed explicitly from the
// products (one triangle, mirrored) while Q is built, so that only Q is stored.
struct PencilProjection {
  Eigen::MatrixXd k, c;
};
PencilProjection ProjectPencil(const NodeArrayOperator& stiffness, double stiffening,
                               const NodeArrayOperator& dampers, double beta, double h,
                               const Eigen::Matrix3Xd& start, int steps) {
  const double a = 0.25 * h * h * stiffening, b = 0.5 * h * beta;
  std::vector<Eigen::Matrix3Xd> basis;
  Eigen::MatrixXd k = Eigen::MatrixXd::Zero(steps, steps), c = k;
  Eigen::Matrix3Xd kq(3, start.cols()), cq(3, start.cols());
  BuildKrylovBasis(
      [&](int m) {
        stiffness(basis[m], &kq);
        dampers(basis[m], &cq);
        for (int i = 0; i <= m; ++i) {
          k(i, m) = k(m, i) = (basis[i].array() * kq.array()).sum();
          c(i, m) = c(m, i) = (basis[i].array() * cq.array()).sum();
        }
        return Eigen::Matrix3Xd(a * kq + b * cq);
      },
      start, steps, &basis);
  const auto size = static_cast<Eigen::Index>(basis.size());
  return {stiffening * k.topLeftCorner(size, size), beta * c.topLeftCorner(size, size)};
}

// The largest h in [lo, hi] with lambda_max((h^2 / 4) k + (h / 2) c) <= 1 for the projections,
// by bisection (the largest eigenvalue grows with h: both matrices are positive semi-definite).
double ProjectedStepRoot(const PencilProjection& projection, double lo, double hi) {
  const auto largest = [&projection](double h) {
    const Eigen::MatrixXd pencil = 0.25 * h * h * projection.k + 0.5 * h * projection.c;
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(pencil, Eigen::EigenvaluesOnly)
        .eigenvalues()
        .maxCoeff();
  };
  for (int iteration = 0; iteration < 40 && hi - lo > 1e-6 * hi; ++iteration) {
    const double h = 0.5 * (lo + hi);
    (largest(h) <= 1.0 ? lo : hi) = h;
  }
  return lo;
}

// The sharp damped limit: the largest h with M - (h^2 / 4) K - (h / 2) C positive semi-definite,
// i.e. lambda_max(M^-1/2 ((h^2 / 4) K + (h / 2) C) M^-1/2) = 1, between the sufficient bound
// `lo` (where that eigenvalue is at most 1) and the undamped limit `hi` (at least 1). K's
// highest modes at nu near 1/2 are bulk modes that the dampers (on the springs' own k) barely
// load, so adding the two largest eigenvalues, as the sufficient bound does, overstates the
// pencil's by a few percent. Rayleigh-Ritz on a Krylov basis of the pencil at `lo`: a second
// basis built at the root moved no step of the realtime block (nu 0.45 and 0.49, 5 and 4 mm) by
// 10^-5.
double SharpDampedStep(const NodeArrayOperator& stiffness, double stiffening,
                       const NodeArrayOperator& dampers, double beta, const Eigen::Matrix3Xd& start,
                       double lo, double hi) {
  const int steps = std::min(60, 3 * static_cast<int>(start.cols()));
  return ProjectedStepRoot(ProjectPencil(stiffness, stiffening, dampers, beta, lo, start, steps),
                           lo, hi);
}

}  // namespace

double StableTimeStep(const Model& model, const StableTimeStepOptions& options) {
  Validate(options);
  // Free particles: nothing elastic limits the step.
  const Eigen::Array<double, 1, Eigen::Dynamic> free = FreeMask(model, options.fixed_nodes);
  // Free particles, or nothing free to move: nothing elastic limits the step.
  if (model.num_springs() == 0 || (free == 0.0).all()) {
    return std::numeric_limits<double>::infinity();
  }
  ForceEvaluator evaluator(model);
  evaluator.Linearize(model.rest_positions());
  const NodeArrayOperator stiffness =
      MassScaled([&evaluator](const Eigen::Matrix3Xd& v,
                              Eigen::Matrix3Xd* out) { evaluator.ApplyStiffness(v, out); },
                 model.masses(), free);
  Eigen::Matrix3Xd start = AlternatingStart(model.num_nodes());
  if (!options.fixed_nodes.empty()) {
    start = (start.array().rowwise() * free).matrix();
    start /= start.norm();
  }
  const double stiffening = Stiffening(model, options);
  const double lambda = stiffening * LargestEigenvalueByRayleighRitz(stiffness, start);
  if (options.damping_beta == 0.0) return options.safety * 2.0 / std::sqrt(lambda);
  const NodeArrayOperator dampers = MassScaled(DamperMatrix(model), model.masses(), free);
  const double lambda_damper = LargestEigenvalueByRayleighRitz(dampers, start);
  const double sufficient = StepForLargestEigenvalues(lambda, lambda_damper, options.damping_beta);
  return options.safety * SharpDampedStep(stiffness, stiffening, dampers, options.damping_beta,
                                          start, sufficient, 2.0 / std::sqrt(lambda));
}

}  // namespace msm_sim::core
