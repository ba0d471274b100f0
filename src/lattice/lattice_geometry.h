#pragma once
// Private to msm_sim's lattice builders: geometry of a (possibly rotated) cubic lattice filling a
// box [0, size], and the element grid of constructions made of cubic elements.

#include <array>
#include <vector>

#include <Eigen/Core>

#include "msm_sim/lattice/lattice_options.h"

namespace msm_sim::core::lattice {

/// The box and lattice every cubic construction starts from.
struct BoxLattice {
  Eigen::Vector3d size;           ///< m
  double spacing;                 ///< m
  Eigen::Vector3d rotation_axis;  ///< about the box centre
  double rotation_angle;          ///< rad
  int max_nodes;
};

/// The box `size` filled with `lattice`'s spacing, rotation and node limit.
inline BoxLattice BoxOf(const Eigen::Vector3d& size, const LatticeOptions& lattice) {
  return {size, lattice.spacing, lattice.rotation_axis, lattice.rotation_angle, lattice.max_nodes};
}

/// Throws std::invalid_argument for non-finite or non-positive sizes or spacing, or a spacing
/// larger than the smallest edge. Shared by every lattice builder.
void ValidateSizeAndSpacing(const Eigen::Vector3d& size, double spacing);

/// ValidateSizeAndSpacing, and more than max_nodes expected nodes or a bad rotation.
void Validate(const BoxLattice& box);

// The 9 neighbour offsets with a positive leading component; with their negatives they form the
// 18 A (edge) and B (face-diagonal) neighbours of a cubic lattice node.
constexpr int kNumHalfOffsets = 9;
extern const std::array<Eigen::Vector3i, kNumHalfOffsets> kHalfOffsets;

/// Index of d or -d in kHalfOffsets (*negated says which); kNumHalfOffsets for anything else
/// (body diagonals, zero).
int HalfOffsetIndex(const Eigen::Vector3i& d, bool* negated);

/// A dense grid of integer lattice coordinates inside [lo, hi] mapping to node indices (-1: none).
class LatticeIndex {
 public:
  /// Throws std::invalid_argument if the grid would be unreasonably large.
  LatticeIndex(const Eigen::Vector3i& lo, const Eigen::Vector3i& hi);
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

/// Maps integer lattice coordinates (in units of `unit`) to positions in the box frame.
struct LatticeFrame {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d centre;
  Eigen::Vector3d offset;  // in lattice units, so that an unrotated lattice is centred in the box
  double unit;

  Eigen::Vector3d Position(const Eigen::Vector3i& c) const {
    return centre + rotation * ((c.cast<double>() + offset) * unit);
  }
  /// Integer range that covers every lattice point whose position can fall inside the box.
  void CoveringRange(const Eigen::Vector3d& size, Eigen::Vector3i* lo, Eigen::Vector3i* hi) const;
};

/// The cell lattice of the box: cell centres, offset so that an unrotated lattice with an integer
/// number of cells along an axis exactly tiles it.
LatticeFrame CellFrame(const BoxLattice& box);

bool InsideBox(const Eigen::Vector3d& p, const Eigen::Vector3d& size, double tolerance);

/// Throws std::invalid_argument if count exceeds max_nodes.
void CheckNodeBudget(long long count, int max_nodes);

/// The cubic elements whose centres fall inside the box and their corners, numbered in order of
/// first appearance. Corner integer coordinate c + delta (delta in {0,1}^3) of element c.
struct ElementGrid {
  std::vector<Eigen::Vector3i> elements;
  std::vector<Eigen::Vector3i> corners;
  LatticeIndex corner_index;
  LatticeFrame corner_frame;

  static Eigen::Vector3i CornerOffset(int delta) {
    return Eigen::Vector3i(delta & 1, (delta >> 1) & 1, (delta >> 2) & 1);
  }
  int Corner(const Eigen::Vector3i& element, int delta) const {
    return corner_index.Find(element + CornerOffset(delta));
  }
};

/// Throws std::invalid_argument if no element fits or the node budget is exceeded.
ElementGrid MakeElementGrid(const BoxLattice& box);

}  // namespace msm_sim::core::lattice
