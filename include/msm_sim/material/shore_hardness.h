#pragma once
// Young's modulus from a datasheet's Shore hardness (docs/materials.md): Gent's relation for
// Shore A, and a published Shore 00 / Shore A comparison table followed by Gent for Shore 00.
// These are empirical correlations that scatter by tens of percent; docs/materials.md gives the
// sources, the ranges and how far they sit from measured moduli.

#include <string>

namespace msm_sim::core {

/// A closed range of hardness readings on one durometer scale.
struct ShoreRange {
  double min = 0.0;
  double max = 0.0;
};

/// The outcome of one hardness-to-modulus conversion.
struct ShoreConversion {
  double youngs = 0.0;   ///< Pa, Gent's relation at shore_a
  double shore_a = 0.0;  ///< the Shore A hardness Gent's relation was evaluated at
  /// The reading converted from on the 00 scale; < 0 when the input was Shore A.
  double shore_00 = -1.0;
  std::string conversion;  ///< which relations were applied, with their sources
  ShoreRange valid_range;  ///< on the input's scale
};

/// The Shore A readings Gent's relation is used for: ASTM D2240's reliable readings, 20 to 90
/// (docs/materials.md explains the choice).
ShoreRange GentShoreARange();

/// The Shore 00 readings accepted: those the comparison table maps into GentShoreARange().
ShoreRange Shore00Range();

/// Gent's relation, E [MPa] = 0.0981 (56 + 7.62336 S) / (0.137505 (254 - 2.54 S)), returned in
/// Pa. Precondition: shore_a finite and within GentShoreARange(); otherwise throws
/// std::out_of_range with a one-line message naming the value and the range.
double GentYoungsFromShoreA(double shore_a);

/// Shore A from Shore 00 by linear interpolation in the comparison table (docs/materials.md);
/// increasing with shore_00. Precondition: shore_00 finite and within the table, 45 to 98;
/// otherwise throws std::out_of_range.
double ShoreAFromShore00(double shore_00);

/// E from a Shore A reading. Precondition as GentYoungsFromShoreA (throws std::out_of_range).
ShoreConversion YoungsFromShoreA(double shore_a);

/// E from a Shore 00 reading, through its Shore A equivalent. Precondition: shore_00 finite and
/// within Shore00Range(); otherwise throws std::out_of_range with a one-line message.
ShoreConversion YoungsFromShore00(double shore_00);

}  // namespace msm_sim::core
