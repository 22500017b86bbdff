#include "core/config_node.hpp"

#include <algorithm>
#include <filesystem>
#include <vector>

namespace glmbslam {

ConfigNode ConfigNode::load_file(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) {
    throw InputError(path, "config file not found");
  }
  try {
    YAML::Node node = YAML::LoadFile(path);
    if (node.IsNull()) node = YAML::Node(YAML::NodeType::Map);
    if (!node.IsMap()) throw InputError(path, "config file must be a YAML mapping of keys to values");
    return ConfigNode(node, path, "");
  } catch (const YAML::Exception& e) {
    throw InputError(path, std::string("invalid YAML: ") + e.what());
  }
}

ConfigNode ConfigNode::parse(const std::string& text, const std::string& origin) {
  try {
    YAML::Node node = YAML::Load(text);
    if (node.IsNull()) node = YAML::Node(YAML::NodeType::Map);
    if (!node.IsMap()) throw InputError(origin, "config must be a YAML mapping of keys to values");
    return ConfigNode(node, origin, "");
  } catch (const YAML::Exception& e) {
    throw InputError(origin, std::string("invalid YAML: ") + e.what());
  }
}

ConfigNode::ConfigNode(YAML::Node node, std::string file, std::string path)
    : node_(std::move(node)), file_(std::move(file)), path_(std::move(path)) {}

YAML::Node ConfigNode::lookup(const std::string& key) {
  known_.insert(key);
  if (!node_ || !node_.IsMap()) return YAML::Node();
  return node_[key];
}

void ConfigNode::read_choice(const std::string& key, std::string& value,
                             const std::vector<std::string>& choices) {
  read(key, value);
  if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
    std::string list;
    for (const auto& c : choices) list += (list.empty() ? "" : ", ") + c;
    fail(key, "must be one of {" + list + "}, got '" + value + "'");
  }
}

bool ConfigNode::has(const std::string& key) {
  return static_cast<bool>(lookup(key));
}

ConfigNode ConfigNode::child(const std::string& key) {
  YAML::Node c = lookup(key);
  if (c && !c.IsMap()) fail(key, "must be a mapping of keys to values");
  return ConfigNode(c ? c : YAML::Node(YAML::NodeType::Map), file_, path_.empty() ? key : path_ + "." + key);
}

namespace {

/// Levenshtein distance (insertions, deletions, substitutions) between two short keys.
std::size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

}  // namespace

std::string ConfigNode::unknown_key_hint(const std::string& key) const {
  // the closest known key within a few edits (a typo), else the keys this mapping knows
  const std::string* best = nullptr;
  std::size_t best_distance = std::max<std::size_t>(2, key.size() / 4) + 1;
  for (const std::string& k : known_) {
    const std::size_t d = edit_distance(key, k);
    if (d < best_distance) best = &k, best_distance = d;
  }
  if (best != nullptr) return " (did you mean '" + *best + "'?)";
  std::string list;
  for (const std::string& k : known_) list += (list.empty() ? "" : ", ") + k;
  return list.empty() ? " (this mapping takes no keys)" : " (known here: " + list + ")";
}

void ConfigNode::finish() const {
  if (node_ && node_.IsMap()) {
    for (const auto& kv : node_) {
      // A key that is not a scalar (a sequence or mapping used as a key) is never a known setting.
      if (!kv.first.IsScalar())
        fail(YAML::Dump(kv.first), "is not a known setting (keys must be plain names)");
      const std::string key = kv.first.Scalar();
      if (known_.count(key) == 0) fail(key, "is not a known setting" + unknown_key_hint(key));
    }
  }
}

void ConfigNode::fail(const std::string& key, const std::string& problem) const {
  const std::string full = path_.empty() ? key : path_ + "." + key;
  throw ConfigError(file_ + ": key '" + full + "' " + problem);
}

}  // namespace glmbslam
