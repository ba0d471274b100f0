#pragma once

#include <istream>
#include <vector>

namespace msm_sim::core {

/// One measured point of a spherical probe pressed into a sample: depth past first contact (m)
/// and the force on the probe (N, pushing it back out).
struct IndentationPoint {
  double depth = 0.0;
  double force = 0.0;
};

/// Reads a measured indentation curve from CSV text: one `depth_m,force_N` row per line, an
/// optional header line first (a line whose first field is not a number, e.g. "depth_m,force_N"),
/// blank lines and lines starting with '#' ignored, fields separated by ',' (spaces around them
/// allowed).
/// Throws std::invalid_argument with a one-line message naming the line number for: no data row,
/// a row without exactly two fields, a field that is not a number, a NaN or infinite value, a
/// negative depth, or a depth not greater than the previous row's (the probe only goes deeper).
std::vector<IndentationPoint> ReadIndentationCurve(std::istream& csv);

}  // namespace msm_sim::core
