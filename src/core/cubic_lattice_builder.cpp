#include "msm_sim/core/cubic_lattice_builder.h"

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "msm_sim/core/extended_msm.h"
#include "msm_sim/core/model_builder.h"

namespace msm_sim::core {
namespace {

// The 9 neighbour offsets with a positive leading component; with their negatives they form the
// 18 A (edge) and B (face-diagonal) neighbours of a cubic lattice node.
constexpr int kNumHalfOffsets = 9;
const std::array<Eigen::Vector3i, kNumHalfOffsets> kHalfOffsets = {
    Eigen::Vector3i(1, 0, 0),  Eigen::Vector3i(0, 1, 0),  Eigen::Vector3i(0, 0, 1),
    Eigen::Vector3i(1, 1, 0),  Eigen::Vector3i(1, -1, 0), Eigen::Vector3i(1, 0, 1),
    Eigen::Vector3i(1, 0, -1), Eigen::Vector3i(0, 1, 1),  Eigen::Vector3i(0, 1, -1)};

// Index of d in kHalfOffsets, or -(index + 1) if -d is there; 0-based. Returns kNumHalfOffsets
// for anything else (body diagonals, zero).
int HalfOffsetIndex(const Eigen::Vector3i& d, bool* negated) {
  for (int o = 0; o < kNumHalfOffsets; ++o) {
    if (d == kHalfOffsets[o]) {
      *negated = false;
      return o;
    }
    if (d == -kHalfOffsets[o]) {
      *negated = true;
      return o;
    }
  }
  return kNumHalfOffsets;
}

void Validate(const CubicLatticeOptions& options) {
  if (!options.size.allFinite() || (options.size.array() <= 0.0).any()) {
    throw std::invalid_argument("box size must be finite and > 0 along every axis");
  }
  if (!std::isfinite(options.spacing) || options.spacing <= 0.0) {
    throw std::invalid_argument("lattice spacing must be finite and > 0");
  }
  if (options.spacing > options.size.minCoeff()) {
    throw std::invalid_argument("lattice spacing " + std::to_string(options.spacing) +
                                " m is larger than the smallest box edge " +
                                std::to_string(options.size.minCoeff()) + " m");
  }
  const double expected_nodes = options.size.prod() / std::pow(options.spacing, 3);
  if (expected_nodes > options.max_nodes) {
    throw std::invalid_argument(
        "the lattice would have about " + std::to_string(static_cast<long long>(expected_nodes)) +
        " nodes, more than " + std::to_string(options.max_nodes) + "; use a larger spacing");
  }
  if (!std::isfinite(options.rotation_angle) || !options.rotation_axis.allFinite() ||
      (options.rotation_angle != 0.0 && options.rotation_axis.norm() == 0.0)) {
    throw std::invalid_argument("lattice rotation needs a finite angle and a non-zero axis");
  }
}

// 4 bytes per cell: at most 1.6 GB for the index of a lattice of about max_nodes nodes.
constexpr double kMaxIndexCells = 4e8;

// A dense grid of integer lattice coordinates inside [lo, hi] mapping to node indices (-1: none).
class LatticeIndex {
 public:
  LatticeIndex(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi)
      : lo_(lo), extent_(hi - lo + Eigen::Vector3i::Ones()) {
    const double cells = static_cast<double>(extent_.x()) * extent_.y() * extent_.z();
    // The index is dense over the lattice range covering the (possibly rotated) box.
    if (cells > kMaxIndexCells) {
      throw std::invalid_argument("the lattice index would need " + std::to_string(cells) +
                                  " cells; use a larger spacing");
    }
    nodes_.assign(static_cast<std::size_t>(cells), -1);
  }
  bool Contains(const Eigen::Vector3i& c) const {
    const Eigen::Vector3i r = c - lo_;
    return (r.array() >= 0).all() && (r.array() < extent_.array()).all();
  }
  int& At(const Eigen::Vector3i& c) { return nodes_[Flat(c)]; }
  int Find(const Eigen::Vector3i& c) const { return Contains(c) ? nodes_[Flat(c)] : -1; }

 private:
  std::size_t Flat(const Eigen::Vector3i& c) const {
    const Eigen::Vector3i r = c - lo_;
    return (static_cast<std::size_t>(r.z()) * extent_.y() + r.y()) * extent_.x() + r.x();
  }
  Eigen::Vector3i lo_;
  Eigen::Vector3i extent_;
  std::vector<int> nodes_;
};

// Maps integer lattice coordinates (in units of `unit`) to positions in the box frame.
struct LatticeFrame {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d centre;
  Eigen::Vector3d offset;  // in lattice units, so that an unrotated lattice is centred in the box
  double unit;

  Eigen::Vector3d Position(const Eigen::Vector3i& c) const {
    return centre + rotation * ((c.cast<double>() + offset) * unit);
  }
  // Integer range that covers every lattice point whose position can fall inside the box.
  void CoveringRange(const Eigen::Vector3d& size, Eigen::Vector3i* lo, Eigen::Vector3i* hi) const {
    Eigen::Vector3d min = Eigen::Vector3d::Constant(1e300);
    Eigen::Vector3d max = -min;
    for (int corner = 0; corner < 8; ++corner) {
      const Eigen::Vector3d p(corner & 1 ? size.x() : 0.0, corner & 2 ? size.y() : 0.0,
                              corner & 4 ? size.z() : 0.0);
      const Eigen::Vector3d l = rotation.transpose() * (p - centre) / unit - offset;
      min = min.cwiseMin(l);
      max = max.cwiseMax(l);
    }
    *lo = min.array().floor().cast<int>() - 1;
    *hi = max.array().ceil().cast<int>() + 1;
  }
};

bool InsideBox(const Eigen::Vector3d& p, const Eigen::Vector3d& size, double tolerance) {
  return (p.array() >= -tolerance).all() && (p.array() <= size.array() + tolerance).all();
}

LatticeFrame MakeFrame(const CubicLatticeOptions& options, double unit, double parity_shift) {
  LatticeFrame frame;
  frame.rotation =
      options.rotation_angle == 0.0
          ? Eigen::Matrix3d::Identity()
          : Eigen::AngleAxisd(options.rotation_angle, options.rotation_axis.normalized())
                .toRotationMatrix();
  frame.centre = 0.5 * options.size;
  frame.unit = unit;
  // Centre the unrotated lattice in the box: with an even number of cells along an axis the
  // cell centres sit at half-integers from the box centre.
  for (int axis = 0; axis < 3; ++axis) {
    const long cells = std::lround(options.size[axis] / options.spacing);
    frame.offset[axis] = (cells % 2 == 0) ? parity_shift : 0.0;
  }
  return frame;
}

void CheckNodeBudget(long long count, int max_nodes) {
  if (count > max_nodes) {
    throw std::invalid_argument("the lattice would have more than " + std::to_string(max_nodes) +
                                " nodes; use a larger spacing");
  }
}

ModelBuilder MakeBuilder(const Material& material, const CubicLatticeOptions& options) {
  ModelBuilder builder(material);
  builder.SetSpringLaw(options.spring_law);
  builder.SetDispersionFraction(DispersionFraction(material.poisson_ratio()));
  return builder;
}

Model BuildNodeCentred(const Material& material, const CubicLatticeOptions& options) {
  const double a = options.spacing;
  const double kappa = material.shear_modulus() * a;
  const double node_mass = material.density() * a * a * a;
  const LatticeFrame frame = MakeFrame(options, a, 0.5);
  Eigen::Vector3i lo, hi;
  frame.CoveringRange(options.size, &lo, &hi);
  LatticeIndex index(lo, hi);

  ModelBuilder builder = MakeBuilder(material, options);
  std::vector<Eigen::Vector3i> coords;
  const double tolerance = 1e-9 * a;
  for (int k = lo.z(); k <= hi.z(); ++k) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        const Eigen::Vector3d p = frame.Position(c);
        if (!InsideBox(p, options.size, tolerance)) continue;
        CheckNodeBudget(static_cast<long long>(coords.size()) + 1, options.max_nodes);
        index.At(c) = builder.AddNode(p, node_mass);
        coords.push_back(c);
      }
    }
  }
  if (coords.empty()) throw std::invalid_argument("no lattice node falls inside the box");

  const int n = static_cast<int>(coords.size());
  std::vector<SpringIndex> spring_of(static_cast<std::size_t>(n) * kNumHalfOffsets, -1);
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const int other = index.Find(coords[node] + kHalfOffsets[o]);
      if (other >= 0) spring_of[node * kNumHalfOffsets + o] = builder.AddSpring(node, other, kappa);
    }
  }

  if (options.compensate_surface) {
    // Missing neighbours mirrored onto each spring end (a, b); see BuildCubicLattice.
    std::vector<int> mirrored(2 * static_cast<std::size_t>(builder.num_springs()), 0);
    for (int node = 0; node < n; ++node) {
      for (int o = 0; o < kNumHalfOffsets; ++o) {
        for (const int sign : {1, -1}) {
          const Eigen::Vector3i d = sign * kHalfOffsets[o];
          if (index.Find(coords[node] + d) >= 0) continue;  // neighbour present
          const int opposite = index.Find(coords[node] - d);
          if (opposite < 0) continue;  // one cell thick along d: nothing to carry it
          // Spring (node, node - d): stored at the endpoint from which it points along +offset.
          const SpringIndex s = sign > 0 ? spring_of[opposite * kNumHalfOffsets + o]
                                         : spring_of[node * kNumHalfOffsets + o];
          builder.AddStiffness(s, 0.5 * kappa);
          mirrored[2 * s + (builder.spring_node_a(s) == node ? 0 : 1)] += 1;
        }
      }
    }
    // In node i's star the spring (i, i - d) stands for itself and for each mirrored neighbour
    // (m copies at end i). Its tension k dL, with k = kappa (m_a + m_b) / 2, is shared by the
    // ends in proportion: weight v = 2 m / (m_a + m_b), so each end counts its own copies at the
    // nominal kappa dL (and receives m copies' share of the dispersion, w = v k L0^2).
    for (SpringIndex s = 0; s < builder.num_springs(); ++s) {
      const double ma = 1.0 + mirrored[2 * s];
      const double mb = 1.0 + mirrored[2 * s + 1];
      builder.SetDispersionWeight(s, builder.spring_node_a(s), 2.0 * ma / (ma + mb));
      builder.SetDispersionWeight(s, builder.spring_node_b(s), 2.0 * mb / (ma + mb));
    }
  }
  return builder.Build(n * a * a * a, a);
}

Model BuildElementCorner(const Material& material, const CubicLatticeOptions& options) {
  const double a = options.spacing;
  const double kappa = material.shear_modulus() * a;
  // Element centres sit on the cell lattice; their corners sit on the same lattice shifted by
  // (1/2, 1/2, 1/2) cells.
  const LatticeFrame cells = MakeFrame(options, a, 0.5);
  Eigen::Vector3i lo, hi;
  cells.CoveringRange(options.size, &lo, &hi);
  const double tolerance = 1e-9 * a;

  std::vector<Eigen::Vector3i> elements;
  for (int k = lo.z(); k <= hi.z(); ++k) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        if (InsideBox(cells.Position(c), options.size, tolerance)) elements.push_back(c);
      }
    }
  }
  if (elements.empty()) throw std::invalid_argument("no lattice element falls inside the box");
  CheckNodeBudget(static_cast<long long>(elements.size()), options.max_nodes);

  // Corners: integer coordinate c + delta labels the corner at cell-lattice point c + delta - 1/2.
  LatticeIndex corner_index(lo, hi + Eigen::Vector3i::Ones());
  LatticeFrame corners = cells;
  corners.offset -= Eigen::Vector3d::Constant(0.5);
  std::vector<Eigen::Vector3i> corner_coords;
  std::vector<double> corner_mass;
  const double corner_share = material.density() * a * a * a / 8.0;
  for (const Eigen::Vector3i& e : elements) {
    for (int delta = 0; delta < 8; ++delta) {
      const Eigen::Vector3i c = e + Eigen::Vector3i(delta & 1, (delta >> 1) & 1, (delta >> 2) & 1);
      int& node = corner_index.At(c);
      if (node < 0) {
        node = static_cast<int>(corner_coords.size());
        corner_coords.push_back(c);
        corner_mass.push_back(0.0);
      }
      corner_mass[node] += corner_share;
    }
  }
  const int n = static_cast<int>(corner_coords.size());
  CheckNodeBudget(n, options.max_nodes);

  // Accumulate per (node, half offset) stiffness from every element sharing the spring.
  std::vector<double> stiffness(static_cast<std::size_t>(n) * kNumHalfOffsets, 0.0);
  for (const Eigen::Vector3i& e : elements) {
    for (int p = 0; p < 8; ++p) {
      for (int q = p + 1; q < 8; ++q) {
        const Eigen::Vector3i cp = e + Eigen::Vector3i(p & 1, (p >> 1) & 1, (p >> 2) & 1);
        const Eigen::Vector3i cq = e + Eigen::Vector3i(q & 1, (q >> 1) & 1, (q >> 2) & 1);
        const Eigen::Vector3i d = cq - cp;
        const int nonzero = (d.array() != 0).count();
        if (nonzero == 3) continue;  // body diagonal: not part of the A+B model
        bool negated = false;
        const int o = HalfOffsetIndex(d, &negated);
        const int from = corner_index.Find(negated ? cq : cp);
        stiffness[from * kNumHalfOffsets + o] += (nonzero == 1 ? 0.25 : 0.5) * kappa;
      }
    }
  }

  ModelBuilder builder = MakeBuilder(material, options);
  for (int node = 0; node < n; ++node) {
    builder.AddNode(corners.Position(corner_coords[node]), corner_mass[node]);
  }
  for (int node = 0; node < n; ++node) {
    for (int o = 0; o < kNumHalfOffsets; ++o) {
      const double k = stiffness[node * kNumHalfOffsets + o];
      if (k <= 0.0) continue;
      const int other = corner_index.Find(corner_coords[node] + kHalfOffsets[o]);
      // A spring shared by fewer elements than in the bulk stands for that fraction of a bulk
      // spring in both end stars: its tension and k already carry the fraction into the inflow
      // and (through w = v k L0^2) into the share of dispersed momentum it receives, so v = 1.
      builder.AddSpring(node, other, k);
    }
  }
  return builder.Build(static_cast<double>(elements.size()) * a * a * a, a);
}

}  // namespace

Model BuildCubicLattice(const Material& material, const CubicLatticeOptions& options) {
  Validate(options);
  return options.construction == CubicConstruction::kNodeCentred
             ? BuildNodeCentred(material, options)
             : BuildElementCorner(material, options);
}

}  // namespace msm_sim::core
