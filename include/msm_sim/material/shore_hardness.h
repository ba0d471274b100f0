#pragma once
// Young's modulus from a datasheet's Shore hardness (docs/materials.md). Shore A 20 to 90: Gent's
// relation. Shore 00 70 to 98: a published Shore 00 / Shore A comparison table, then Gent. The
// soft end, Shore 00 10 to 70 and Shore A 10 to 20 (through the table): the type 00 durometer's
// sphere pressed into an elastic half-space (Sneddon's solution) at the durometer's spring force
// and depth. These are correlations that scatter by tens of percent (Gent) and by up to a factor
// of 2 (the soft end); docs/materials.md gives the sources, the ranges and the comparison with
// datasheet moduli.

#include <string>

namespace msm_sim::core {

/// A closed range of hardness readings on one durometer scale.
struct ShoreRange {
  double min = 0.0;
  double max = 0.0;
};

/// The outcome of one hardness-to-modulus conversion.
struct ShoreConversion {
  double youngs = 0.0;  ///< Pa
  /// The Shore A reading: the input, or the 00 input's equivalent by the comparison table; < 0
  /// when the table has none (Shore 00 below 45).
  double shore_a = -1.0;
  /// The reading converted from on the 00 scale; < 0 when the input was Shore A.
  double shore_00 = -1.0;
  std::string conversion;   ///< which relations were applied, with their sources
  std::string uncertainty;  ///< how far from measured moduli the relation is known to be
  ShoreRange valid_range;   ///< on the input's scale
};

/// The Shore A readings accepted, 10 to 90: Gent's relation from 20, below it the comparison
/// table to Shore 00 and the sphere relation (docs/materials.md).
ShoreRange ShoreARange();

/// The Shore A readings Gent's relation is used for: ASTM D2240's reliable readings, 20 to 90
/// (docs/materials.md explains the choice).
ShoreRange GentShoreARange();

/// The Shore 00 readings accepted, 10 to 98: the sphere relation below 70, the comparison table
/// and Gent's relation from 70 (00 70 is Shore A 20) to the table's last row.
ShoreRange Shore00Range();

/// The Shore 00 readings the sphere relation is used for: 10 to 70.
ShoreRange SphereShore00Range();

/// Gent's relation, E [MPa] = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)), returned in
/// Pa. Precondition: shore_a finite and within GentShoreARange(); otherwise throws
/// std::out_of_range with a one-line message naming the value and the range.
double GentYoungsFromShoreA(double shore_a);

/// The type 00 durometer's relation, in Pa: its 1.19 mm sphere pressed to the depth
/// h = 2.54 (1 - S/100) mm by its spring, F = 0.203 + 0.00908 S N, into an incompressible
/// elastic half-space; Sneddon's solution for a sphere, h = (a/2) ln((R+a)/(R-a)) and
/// F = E/(1 - nu^2) [(a^2 + R^2)/2 ln((R+a)/(R-a)) - a R] with nu = 0.5, solved for E.
/// Precondition: shore_00 finite and within SphereShore00Range(); otherwise throws
/// std::out_of_range.
double SphereYoungsFromShore00(double shore_00);

/// Shore A from Shore 00 by linear interpolation in the comparison table (docs/materials.md);
/// increasing with shore_00. Precondition: shore_00 finite and within the table, 45 to 98;
/// otherwise throws std::out_of_range.
double ShoreAFromShore00(double shore_00);

/// E from a Shore A reading. Precondition: shore_a finite and within ShoreARange(); otherwise
/// throws std::out_of_range with a one-line message.
ShoreConversion YoungsFromShoreA(double shore_a);

/// E from a Shore 00 reading. Precondition: shore_00 finite and within Shore00Range();
/// otherwise throws std::out_of_range with a one-line message.
ShoreConversion YoungsFromShore00(double shore_00);

}  // namespace msm_sim::core
