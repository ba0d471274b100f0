#pragma once
// Private to the experiments' CSV readers (indentation_curve.cpp, tensile_curve.cpp): a field's
// trimming and its reading as one whole number.

#include <cstdlib>
#include <string>

namespace msm_sim::core::internal {

/// `text` without the leading and trailing characters found in `blanks`.
inline std::string Trimmed(const std::string& text, const char* blanks = " \t\r") {
  const auto begin = text.find_first_not_of(blanks);
  if (begin == std::string::npos) return "";
  const auto end = text.find_last_not_of(blanks);
  return text.substr(begin, end - begin + 1);
}

/// True, with *value set, when all of `text` is one number in strtod's syntax (which accepts
/// "nan" and "inf": callers refuse those with their own message); false for "" or anything more.
inline bool ParseWholeNumber(const std::string& text, double* value) {
  if (text.empty()) return false;
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return end == text.c_str() + text.size();
}

}  // namespace msm_sim::core::internal
