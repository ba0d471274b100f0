#pragma once

#include <istream>
#include <string>
#include <vector>

namespace msm_sim::core {

/// One point of a uniaxial tensile test: engineering strain (ΔL / L0, a fraction) and engineering
/// stress (force over the undeformed cross-section, Pa).
struct TensilePoint {
  double strain = 0.0;
  double stress = 0.0;
};

/// Which columns of a tensile CSV hold the curve. A column is given by its name in the column
/// header line (case and surrounding spaces ignored) or, when `*_index` >= 0, by its 0-based
/// index. Empty names and negative indices select the defaults: the first column whose name
/// starts with "engineering strain" / "engineering stress".
struct TensileColumns {
  std::string strain_name;
  std::string stress_name;
  int strain_index = -1;
  int stress_index = -1;
  /// "Pa", "kPa" or "MPa"; empty: read from the stress column's name ("(MPa)", "[kPa]", ...).
  std::string stress_unit;
};

/// A curve as read, with what it was read from (for the fit's provenance).
struct TensileCurve {
  std::vector<TensilePoint> points;  ///< in file order, strain non-decreasing
  std::string strain_column;         ///< the columns' names (or "column N" without a header)
  std::string stress_column;
  std::string stress_unit;         ///< the unit the stresses were given in
  double stress_scale = 1.0;       ///< Pa per unit of the file
  bool strain_in_percent = false;  ///< the strain column's name holds "%": divided by 100
};

/// Reads a tensile curve from CSV text. The separator is ';' if the column header line (or, with
/// no header, the first data line) contains one, else ','. Lines before the column header (a
/// specimen's header block) are skipped; the column header is the first line where both chosen
/// columns hold non-numeric text (with names: the first line holding both names). Blank lines,
/// lines of separators only and lines starting with '#' are skipped after it; every other line is
/// a data row. Throws std::invalid_argument with a one-line message for: a column name not found,
/// no stress unit given or found (or a given one that contradicts the column's name), no data
/// row, and, naming the file's line number, a row without the chosen fields, a field that is not
/// a finite number, or a strain below the previous row's.
TensileCurve ReadTensileCurve(std::istream& csv, const TensileColumns& columns);

/// Pa per unit of "Pa", "kPa" or "MPa" (case-insensitive); 0 for anything else.
double StressUnitScale(const std::string& unit);

}  // namespace msm_sim::core
