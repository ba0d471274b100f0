#include "lattice/lattice_geometry.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace msm_sim::core::lattice {
namespace {
// 4 bytes per cell: at most 1.6 GB for the index of a lattice of about max_nodes nodes.
constexpr double kMaxIndexCells = 4e8;
}  // namespace

const std::array<Eigen::Vector3i, kNumHalfOffsets> kHalfOffsets = {
    Eigen::Vector3i(1, 0, 0),  Eigen::Vector3i(0, 1, 0),  Eigen::Vector3i(0, 0, 1),
    Eigen::Vector3i(1, 1, 0),  Eigen::Vector3i(1, -1, 0), Eigen::Vector3i(1, 0, 1),
    Eigen::Vector3i(1, 0, -1), Eigen::Vector3i(0, 1, 1),  Eigen::Vector3i(0, 1, -1)};

void ValidateSizeAndSpacing(const Eigen::Vector3d& size, double spacing) {
  if (!size.allFinite() || (size.array() <= 0.0).any()) {
    throw std::invalid_argument("box size must be finite and > 0 along every axis");
  }
  if (!std::isfinite(spacing) || spacing <= 0.0) {
    throw std::invalid_argument("lattice spacing must be finite and > 0");
  }
  if (spacing > size.minCoeff()) {
    throw std::invalid_argument("lattice spacing " + std::to_string(spacing) +
                                " m is larger than the smallest box edge " +
                                std::to_string(size.minCoeff()) + " m");
  }
}

void Validate(const BoxLattice& box) {
  ValidateSizeAndSpacing(box.size, box.spacing);
  const double expected_nodes = box.size.prod() / std::pow(box.spacing, 3);
  if (expected_nodes > box.max_nodes) {
    throw std::invalid_argument(
        "the lattice would have about " + std::to_string(static_cast<long long>(expected_nodes)) +
        " nodes, more than " + std::to_string(box.max_nodes) + "; use a larger spacing");
  }
  if (!std::isfinite(box.rotation_angle) || !box.rotation_axis.allFinite() ||
      (box.rotation_angle != 0.0 && box.rotation_axis.norm() == 0.0)) {
    throw std::invalid_argument("lattice rotation needs a finite angle and a non-zero axis");
  }
}

int HalfOffsetIndex(const Eigen::Vector3i& d, bool* negated) {
  for (int o = 0; o < kNumHalfOffsets; ++o) {
    if (d == kHalfOffsets[o] || d == -kHalfOffsets[o]) {
      *negated = d != kHalfOffsets[o];
      return o;
    }
  }
  return kNumHalfOffsets;
}

LatticeIndex::LatticeIndex(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi)
    : lo_(lo), extent_(hi - lo + Eigen::Vector3i::Ones()) {
  const double cells = static_cast<double>(extent_.x()) * extent_.y() * extent_.z();
  // The index is dense over the lattice range covering the (possibly rotated) box.
  if (cells > kMaxIndexCells) {
    throw std::invalid_argument("the lattice index would need " + std::to_string(cells) +
                                " cells; use a larger spacing");
  }
  nodes_.assign(static_cast<std::size_t>(cells), -1);
}

void LatticeFrame::CoveringRange(const Eigen::Vector3d& size, Eigen::Vector3i* lo,
                                 Eigen::Vector3i* hi) const {
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

LatticeFrame CellFrame(const BoxLattice& box) {
  LatticeFrame frame;
  frame.rotation = box.rotation_angle == 0.0
                       ? Eigen::Matrix3d::Identity()
                       : Eigen::AngleAxisd(box.rotation_angle, box.rotation_axis.normalized())
                             .toRotationMatrix();
  frame.centre = 0.5 * box.size;
  frame.unit = box.spacing;
  // Centre the unrotated lattice in the box: with an even number of cells along an axis the
  // cell centres sit at half-integers from the box centre.
  for (int axis = 0; axis < 3; ++axis) {
    const long cells = std::lround(box.size[axis] / box.spacing);
    frame.offset[axis] = (cells % 2 == 0) ? 0.5 : 0.0;
  }
  return frame;
}

bool InsideBox(const Eigen::Vector3d& p, const Eigen::Vector3d& size, double tolerance) {
  return (p.array() >= -tolerance).all() && (p.array() <= size.array() + tolerance).all();
}

void CheckNodeBudget(long long count, int max_nodes) {
  if (count > max_nodes) {
    throw std::invalid_argument("the lattice would have more than " + std::to_string(max_nodes) +
                                " nodes; use a larger spacing");
  }
}

ElementGrid MakeElementGrid(const BoxLattice& box) {
  // Element centres sit on the cell lattice; their corners on the same lattice shifted by
  // (1/2, 1/2, 1/2) cells.
  const LatticeFrame cells = CellFrame(box);
  Eigen::Vector3i lo, hi;
  cells.CoveringRange(box.size, &lo, &hi);
  const double tolerance = 1e-9 * box.spacing;
  LatticeFrame corner_frame = cells;
  corner_frame.offset -= Eigen::Vector3d::Constant(0.5);
  ElementGrid grid{{}, {}, LatticeIndex(lo, hi + Eigen::Vector3i::Ones()), corner_frame};
  for (int k = lo.z(); k <= hi.z(); ++k) {
    for (int j = lo.y(); j <= hi.y(); ++j) {
      for (int i = lo.x(); i <= hi.x(); ++i) {
        const Eigen::Vector3i c(i, j, k);
        if (InsideBox(cells.Position(c), box.size, tolerance)) grid.elements.push_back(c);
      }
    }
  }
  if (grid.elements.empty()) throw std::invalid_argument("no lattice element falls inside the box");
  CheckNodeBudget(static_cast<long long>(grid.elements.size()), box.max_nodes);
  for (const Eigen::Vector3i& e : grid.elements) {
    for (int delta = 0; delta < 8; ++delta) {
      const Eigen::Vector3i c = e + ElementGrid::CornerOffset(delta);
      int& node = grid.corner_index.At(c);
      if (node < 0) {
        node = static_cast<int>(grid.corners.size());
        grid.corners.push_back(c);
      }
    }
  }
  CheckNodeBudget(static_cast<long long>(grid.corners.size()), box.max_nodes);
  return grid;
}

}  // namespace msm_sim::core::lattice
