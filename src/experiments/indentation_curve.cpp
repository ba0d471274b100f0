#include "msm_sim/experiments/indentation_curve.h"

#include <cmath>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "experiments/csv_fields.h"

namespace msm_sim::core {
namespace {

// The whole field as a number (strtod accepts "nan" and "inf", which are refused by the caller
// with their own message); false when anything but a number is there.
bool ParseNumber(const std::string& field, double* value) {
  return internal::ParseWholeNumber(internal::Trimmed(field), value);
}

[[noreturn]] void Refuse(int line, const std::string& what) {
  throw std::invalid_argument("indentation CSV line " + std::to_string(line) + ": " + what);
}

// One data row's two numbers, checked; `previous_depth` < 0 for the first row.
IndentationPoint ParseRow(const std::string& row, int line, double previous_depth) {
  const auto comma = row.find(',');
  if (comma == std::string::npos || row.find(',', comma + 1) != std::string::npos) {
    Refuse(line, "expected two fields depth_m,force_N, got '" + row + "'");
  }
  IndentationPoint point;
  if (!ParseNumber(row.substr(0, comma), &point.depth) ||
      !ParseNumber(row.substr(comma + 1), &point.force)) {
    Refuse(line, "not a number in '" + row + "'");
  }
  if (!std::isfinite(point.depth) || !std::isfinite(point.force)) {
    Refuse(line, "NaN or infinite value in '" + row + "'");
  }
  if (point.depth < 0.0) Refuse(line, "negative depth " + internal::Trimmed(row.substr(0, comma)));
  if (previous_depth >= 0.0 && point.depth <= previous_depth) {
    Refuse(line, "depth " + internal::Trimmed(row.substr(0, comma)) +
                     " is not greater than the previous row's (depths must increase)");
  }
  return point;
}

}  // namespace

std::vector<IndentationPoint> ReadIndentationCurve(std::istream& csv) {
  std::vector<IndentationPoint> curve;
  std::string row;
  bool first_content = true;
  for (int line = 1; std::getline(csv, row); ++line) {
    const std::string text = internal::Trimmed(row);
    if (text.empty() || text[0] == '#') continue;
    double ignored = 0.0;
    const bool header = first_content && !ParseNumber(text.substr(0, text.find(',')), &ignored);
    first_content = false;
    if (header) continue;
    curve.push_back(ParseRow(text, line, curve.empty() ? -1.0 : curve.back().depth));
  }
  if (curve.empty()) throw std::invalid_argument("indentation CSV has no depth_m,force_N rows");
  return curve;
}

}  // namespace msm_sim::core
