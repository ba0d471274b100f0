#pragma once
// Typed, checked reads of a parameter tree (XmlRpc values, as getParam gives them): each read
// returns the fallback for a missing key and throws ConfigError naming the parameter's path for
// a value of the wrong type or range. The configuration's schema (simulation_config.cpp) is
// written in these.

#include <set>
#include <string>

#include <xmlrpcpp/XmlRpcValue.h>
#include <Eigen/Core>

#include "simulation_config.h"

namespace msm_sim::ros_interface::param {

using XmlRpc::XmlRpcValue;

/// Throws ConfigError("parameter <parameter>: <problem>").
[[noreturn]] void Fail(const std::string& parameter, const std::string& problem);

/// True if `value` is a dictionary with `key`.
bool Has(XmlRpcValue& value, const std::string& key);

/// Copies parent[key] into *value if there is one (a copy, as getParam would give it).
bool Get(XmlRpcValue& parent, const std::string& key, XmlRpcValue* value);

// parent[key] at path/key, or the fallback when parent has no key. Numbers may be integers,
// doubles or text that reads as a number (YAML 1.1 reads 1.0e5 as text); they must be finite.
double Number(XmlRpcValue& parent, const std::string& key, double fallback,
              const std::string& path);
double Positive(XmlRpcValue& parent, const std::string& key, double fallback,
                const std::string& path);
double NonNegative(XmlRpcValue& parent, const std::string& key, double fallback,
                   const std::string& path);
std::string Text(XmlRpcValue& parent, const std::string& key, const std::string& fallback,
                 const std::string& path);
bool Flag(XmlRpcValue& parent, const std::string& key, bool fallback, const std::string& path);
/// A list of 3 finite numbers.
Eigen::Vector3d Vector(XmlRpcValue& parent, const std::string& key, const Eigen::Vector3d& fallback,
                       const std::string& path);

/// Fails at path/key unless value <= max; `meaning` says what the bound keeps out. Returns value.
double AtMost(double value, double max, const std::string& key, const std::string& path,
              const std::string& meaning);

/// parent[key] as a name that is a valid ROS base name (a letter, then letters, digits and
/// underscores: it becomes a tf frame, a marker namespace and a parameter namespace) and none
/// of `reserved`; fails at path/key for a missing, malformed or reserved name.
std::string Name(XmlRpcValue& parent, const std::string& key, const std::set<std::string>& reserved,
                 const std::string& path);

/// Fails at `path` unless `value` is a dictionary whose keys are all in `known`: a misspelt
/// key would otherwise be ignored silently and its default used.
void KnownKeys(XmlRpcValue& value, const std::set<std::string>& known, const std::string& path);

/// parent[key] as a whole number in [0, max] (fallback when missing); integers, or doubles and
/// text that read as one. Fails before any cast for larger, negative or fractional values.
double Count(XmlRpcValue& parent, const std::string& key, double fallback, double max,
             const std::string& path);

/// Fails at `parameter`: `value` is none of `allowed` (listed in alphabetical order).
[[noreturn]] void FailNotOneOf(const std::string& value, const std::set<std::string>& allowed,
                               const std::string& parameter);
/// FailNotOneOf unless `value` is one of `allowed`.
void OneOf(const std::string& value, const std::set<std::string>& allowed,
           const std::string& parameter);

}  // namespace msm_sim::ros_interface::param
