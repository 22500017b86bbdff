#pragma once
// Strict, typed reading of YAML configuration files.
//
// Each module keeps its settings in a plain struct whose members hold the defaults; a loader reads a
// ConfigNode into it with `read(key, member)`. Keys absent from the file keep their default; a value of the
// wrong type, and (at `finish()`) any key that was never read, is a ConfigError naming the key and the file,
// so typos never pass silently.
#include <set>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/error.hpp"

namespace glmbslam {

class ConfigNode {
 public:
  /// Loads a YAML file; throws InputError naming the file if it is missing or not valid YAML.
  static ConfigNode load_file(const std::string& path);
  /// Parses YAML text (for tests and built-in configs); `origin` names it in messages.
  static ConfigNode parse(const std::string& text, const std::string& origin);

  ConfigNode(YAML::Node node, std::string file, std::string path);

  /// Reads `key` into `value` if present (else leaves the default). Throws ConfigError on a type mismatch.
  template <typename T>
  void read(const std::string& key, T& value) {
    const YAML::Node child = lookup(key);
    if (!child) return;
    try {
      value = child.as<T>();
    } catch (const YAML::Exception&) {
      fail(key, "has a value of the wrong type (expected " + type_name<T>() + ")");
    }
  }

  /// Reads `key` and checks lo ≤ value ≤ hi.
  template <typename T>
  void read_in_range(const std::string& key, T& value, T lo, T hi) {
    read(key, value);
    if (value < lo || value > hi) {
      fail(key, "is out of range [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    }
  }

  /// Reads a string key that must be one of `choices`.
  void read_choice(const std::string& key, std::string& value, const std::vector<std::string>& choices);

  /// True if the key is present (and marks it as known).
  bool has(const std::string& key);
  /// A nested mapping; missing keys give an empty node (all defaults). Throws if `key` is not a mapping.
  /// Call finish() on the child too once all its keys are read.
  ConfigNode child(const std::string& key);
  /// Throws ConfigError for the first key of this mapping that was never read, suggesting the closest known
  /// key ("did you mean") or listing the known ones.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& problem) const;
  const std::string& file() const { return file_; }

 private:
  std::string unknown_key_hint(const std::string& key) const;
  YAML::Node lookup(const std::string& key);
  template <typename T>
  static std::string type_name();

  YAML::Node node_;
  std::string file_;
  std::string path_;
  std::set<std::string> known_;
};

template <typename T>
std::string ConfigNode::type_name() {
  if constexpr (std::is_same_v<T, bool>) return "true/false";
  if constexpr (std::is_integral_v<T>) return "an integer";
  if constexpr (std::is_floating_point_v<T>) return "a number";
  if constexpr (std::is_same_v<T, std::string>) return "a string";
  return "a list or mapping";
}

}  // namespace glmbslam
