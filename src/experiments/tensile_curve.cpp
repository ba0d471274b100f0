#include "msm_sim/experiments/tensile_curve.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "experiments/csv_fields.h"

namespace msm_sim::core {
namespace {

// A field's blanks: spaces, tabs, carriage returns and the quotes some exports add.
constexpr char kBlanks[] = " \t\r\"";

std::string Lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

std::vector<std::string> Split(const std::string& line, char separator) {
  std::vector<std::string> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t end = line.find(separator, start);
    fields.push_back(internal::Trimmed(line.substr(start, end - start), kBlanks));
    if (end == std::string::npos) return fields;
    start = end + 1;
  }
}

char SeparatorOf(const std::string& line) {
  return line.find(';') != std::string::npos ? ';' : ',';
}

// A line with no content: blank, a comment, or separators only.
bool Empty(const std::string& line) {
  const std::string text = internal::Trimmed(line, kBlanks);
  return text.empty() || text[0] == '#' || text.find_first_not_of(";, \t") == std::string::npos;
}

// The index of one chosen column in a candidate header line, if the line names it.
std::optional<int> ColumnIn(const std::vector<std::string>& fields, const std::string& name,
                            int index, const char* default_prefix) {
  double ignored = 0.0;
  if (index >= 0) {
    if (index < static_cast<int>(fields.size()) && !fields[index].empty() &&
        !internal::ParseWholeNumber(fields[index], &ignored)) {
      return index;
    }
    return std::nullopt;
  }
  for (std::size_t i = 0; i < fields.size(); ++i) {
    const std::string field = Lower(fields[i]);
    const bool match = name.empty() ? field.rfind(default_prefix, 0) == 0 : field == Lower(name);
    if (match) return static_cast<int>(i);
  }
  return std::nullopt;
}

std::string DescribeColumn(const std::string& name, int index, const char* default_prefix) {
  if (index >= 0) return "column " + std::to_string(index);
  if (!name.empty()) return "a column named '" + name + "'";
  return std::string("a column named '") + default_prefix + "...'";
}

[[noreturn]] void Refuse(int line, const std::string& what) {
  throw std::invalid_argument("tensile CSV line " + std::to_string(line) + ": " + what);
}

// The unit a stress column's name states, "(MPa)" or "[kPa]"; empty if none.
std::string UnitInName(const std::string& name) {
  const std::string lower = Lower(name);
  for (const char* unit : {"mpa", "kpa", "pa"}) {
    for (const char* brackets : {"()", "[]"}) {
      const std::string token = std::string(1, brackets[0]) + unit + brackets[1];
      if (lower.find(token) != std::string::npos) {
        return std::string(unit) == "mpa" ? "MPa" : std::string(unit) == "kpa" ? "kPa" : "Pa";
      }
    }
  }
  return "";
}

// Sets the curve's stress unit from the option and the column's name; they must not disagree.
void ResolveUnit(const std::string& given, TensileCurve* curve) {
  const std::string named = UnitInName(curve->stress_column);
  if (!given.empty() && StressUnitScale(given) == 0.0) {
    throw std::invalid_argument("unknown stress unit '" + given + "' (expected Pa, kPa or MPa)");
  }
  if (!given.empty() && !named.empty() && Lower(given) != Lower(named)) {
    throw std::invalid_argument("--stress-unit " + given + " contradicts the column '" +
                                curve->stress_column + "'");
  }
  curve->stress_unit = !given.empty() ? given : named;
  if (curve->stress_unit.empty()) {
    throw std::invalid_argument("the stress column '" + curve->stress_column +
                                "' states no unit; give --stress-unit Pa, kPa or MPa");
  }
  curve->stress_scale = StressUnitScale(curve->stress_unit);
}

struct Layout {
  int header_line = 0;  // 1-based line of the column header, 0 for none
  int strain = 0, stress = 0;
  char separator = ',';
};

Layout FindLayout(const std::vector<std::string>& lines, const TensileColumns& columns,
                  TensileCurve* curve) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (Empty(lines[i])) continue;
    const char separator = SeparatorOf(lines[i]);
    const std::vector<std::string> fields = Split(lines[i], separator);
    const auto strain =
        ColumnIn(fields, columns.strain_name, columns.strain_index, "engineering strain");
    const auto stress =
        ColumnIn(fields, columns.stress_name, columns.stress_index, "engineering stress");
    if (!strain || !stress) continue;
    curve->strain_column = fields[*strain];
    curve->stress_column = fields[*stress];
    return Layout{static_cast<int>(i) + 1, *strain, *stress, separator};
  }
  if (columns.strain_index < 0 || columns.stress_index < 0) {
    throw std::invalid_argument(
        "tensile CSV has no column header with " +
        DescribeColumn(columns.strain_name, columns.strain_index, "Engineering Strain") + " and " +
        DescribeColumn(columns.stress_name, columns.stress_index, "Engineering Stress"));
  }
  curve->strain_column = "column " + std::to_string(columns.strain_index);
  curve->stress_column = "column " + std::to_string(columns.stress_index);
  const auto first = std::find_if(lines.begin(), lines.end(),
                                  [](const std::string& line) { return !Empty(line); });
  return Layout{0, columns.strain_index, columns.stress_index,
                first == lines.end() ? ',' : SeparatorOf(*first)};
}

TensilePoint ParseRow(const std::string& row, int line, const Layout& layout, double scale) {
  const std::vector<std::string> fields = Split(row, layout.separator);
  const int needed = std::max(layout.strain, layout.stress) + 1;
  if (static_cast<int>(fields.size()) < needed) {
    Refuse(line, "expected at least " + std::to_string(needed) + " fields, got '" +
                     internal::Trimmed(row, kBlanks) + "'");
  }
  TensilePoint point;
  if (!internal::ParseWholeNumber(fields[layout.strain], &point.strain) ||
      !internal::ParseWholeNumber(fields[layout.stress], &point.stress)) {
    Refuse(line, "not a number in '" + internal::Trimmed(row, kBlanks) + "'");
  }
  if (!std::isfinite(point.strain) || !std::isfinite(point.stress)) {
    Refuse(line, "NaN or infinite value in '" + internal::Trimmed(row, kBlanks) + "'");
  }
  point.stress *= scale;
  return point;
}

}  // namespace

double StressUnitScale(const std::string& unit) {
  const std::string lower = Lower(unit);
  if (lower == "pa") return 1.0;
  if (lower == "kpa") return 1e3;
  if (lower == "mpa") return 1e6;
  return 0.0;
}

TensileCurve ReadTensileCurve(std::istream& csv, const TensileColumns& columns) {
  std::vector<std::string> lines;
  for (std::string line; std::getline(csv, line);) lines.push_back(line);
  TensileCurve curve;
  const Layout layout = FindLayout(lines, columns, &curve);
  ResolveUnit(columns.stress_unit, &curve);
  curve.strain_in_percent = curve.strain_column.find('%') != std::string::npos;
  const double strain_scale = curve.strain_in_percent ? 0.01 : 1.0;
  for (std::size_t i = layout.header_line; i < lines.size(); ++i) {
    if (Empty(lines[i])) continue;
    const int line = static_cast<int>(i) + 1;
    TensilePoint point = ParseRow(lines[i], line, layout, curve.stress_scale);
    point.strain *= strain_scale;
    if (!curve.points.empty() && point.strain < curve.points.back().strain) {
      Refuse(line, "strain " + std::to_string(point.strain) +
                       " is below the previous row's (a tensile curve only stretches)");
    }
    curve.points.push_back(point);
  }
  if (curve.points.empty()) throw std::invalid_argument("tensile CSV has no data rows");
  return curve;
}

}  // namespace msm_sim::core
