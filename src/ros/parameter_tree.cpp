#include "parameter_tree.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace msm_sim::ros_interface::param {
namespace {

double ToDouble(XmlRpcValue& value, const std::string& parameter) {
  if (value.getType() == XmlRpcValue::TypeDouble) return static_cast<double>(value);
  if (value.getType() == XmlRpcValue::TypeInt) return static_cast<int>(value);
  if (value.getType() == XmlRpcValue::TypeString) {
    // YAML 1.1 (PyYAML, rosparam) reads 1.0e5 without an exponent sign as text; take it.
    const std::string text = static_cast<std::string>(value);
    char* end = nullptr;
    const double number = std::strtod(text.c_str(), &end);
    if (!text.empty() && end == text.c_str() + text.size()) return number;
    Fail(parameter, "expected a number, got '" + text + "'");
  }
  Fail(parameter, "expected a number");
}

}  // namespace

void Fail(const std::string& parameter, const std::string& problem) {
  throw ConfigError("parameter " + parameter + ": " + problem);
}

bool Has(XmlRpcValue& value, const std::string& key) {
  return value.getType() == XmlRpcValue::TypeStruct && value.hasMember(key);
}

double Number(XmlRpcValue& parent, const std::string& key, double fallback,
              const std::string& path) {
  if (!Has(parent, key)) return fallback;
  const double value = ToDouble(parent[key], path + "/" + key);
  if (!std::isfinite(value)) Fail(path + "/" + key, "must be finite");
  return value;
}

double Positive(XmlRpcValue& parent, const std::string& key, double fallback,
                const std::string& path) {
  const double value = Number(parent, key, fallback, path);
  if (!(value > 0.0)) Fail(path + "/" + key, "must be > 0 (got " + std::to_string(value) + ")");
  return value;
}

double NonNegative(XmlRpcValue& parent, const std::string& key, double fallback,
                   const std::string& path) {
  const double value = Number(parent, key, fallback, path);
  if (!(value >= 0.0)) Fail(path + "/" + key, "must be >= 0 (got " + std::to_string(value) + ")");
  return value;
}

std::string Text(XmlRpcValue& parent, const std::string& key, const std::string& fallback,
                 const std::string& path) {
  if (!Has(parent, key)) return fallback;
  if (parent[key].getType() != XmlRpcValue::TypeString) Fail(path + "/" + key, "expected text");
  return static_cast<std::string>(parent[key]);
}

bool Flag(XmlRpcValue& parent, const std::string& key, bool fallback, const std::string& path) {
  if (!Has(parent, key)) return fallback;
  if (parent[key].getType() != XmlRpcValue::TypeBoolean) {
    Fail(path + "/" + key, "expected true or false");
  }
  return static_cast<bool>(parent[key]);
}

Eigen::Vector3d Vector(XmlRpcValue& parent, const std::string& key, const Eigen::Vector3d& fallback,
                       const std::string& path) {
  if (!Has(parent, key)) return fallback;
  XmlRpcValue& list = parent[key];
  if (list.getType() != XmlRpcValue::TypeArray || list.size() != 3) {
    Fail(path + "/" + key, "expected a list of 3 numbers");
  }
  Eigen::Vector3d v;
  for (int i = 0; i < 3; ++i) v[i] = ToDouble(list[i], path + "/" + key);
  if (!v.allFinite()) Fail(path + "/" + key, "must be finite");
  return v;
}

void FailNotOneOf(const std::string& value, const std::set<std::string>& allowed,
                  const std::string& parameter) {
  std::ostringstream list;
  for (const std::string& a : allowed) list << (list.tellp() > 0 ? ", " : "") << a;
  Fail(parameter, "'" + value + "' is not one of " + list.str());
}

void OneOf(const std::string& value, const std::set<std::string>& allowed,
           const std::string& parameter) {
  if (allowed.count(value) == 0) FailNotOneOf(value, allowed, parameter);
}

void KnownKeys(XmlRpcValue& value, const std::set<std::string>& known, const std::string& path) {
  if (value.getType() != XmlRpcValue::TypeStruct) Fail(path, "expected a dictionary");
  for (auto& [key, entry] : value) {
    if (known.count(key) == 0) {
      std::ostringstream list;
      for (const std::string& k : known) list << (list.tellp() > 0 ? ", " : "") << k;
      Fail(path + "/" + key, "unknown parameter (known here: " + list.str() + ")");
    }
  }
}

double Count(XmlRpcValue& parent, const std::string& key, double fallback, double max,
             const std::string& path) {
  const double value = NonNegative(parent, key, fallback, path);
  if (value != std::floor(value)) Fail(path + "/" + key, "must be a whole number");
  if (value > max) {
    std::ostringstream text;
    text << "must be at most " << max << " (got " << value << ")";
    Fail(path + "/" + key, text.str());
  }
  return value;
}

double AtMost(double value, double max, const std::string& key, const std::string& path,
              const std::string& meaning) {
  if (value <= max) return value;
  std::ostringstream text;
  text << "must be at most " << max << " (got " << value << "): " << meaning;
  Fail(path + "/" + key, text.str());
}

std::string Name(XmlRpcValue& parent, const std::string& key, const std::set<std::string>& reserved,
                 const std::string& path) {
  const std::string name = Text(parent, key, "", path);
  if (name.empty()) Fail(path + "/" + key, "missing");
  const bool letter_first = std::isalpha(static_cast<unsigned char>(name[0])) != 0;
  const bool word = std::all_of(name.begin(), name.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
  });
  if (!letter_first || !word) {
    Fail(path + "/" + key, "'" + name +
                               "' is not a ROS name: start with a letter and use only letters, "
                               "digits and underscores");
  }
  if (reserved.count(name) != 0) {
    Fail(path + "/" + key, "'" + name + "' is taken (the world frame and 'ground' are reserved)");
  }
  return name;
}

bool Get(XmlRpcValue& parent, const std::string& key, XmlRpcValue* value) {
  if (!Has(parent, key)) return false;
  *value = parent[key];
  return true;
}

}  // namespace msm_sim::ros_interface::param
