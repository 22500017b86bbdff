#include "core/config_node.hpp"

#include <algorithm>
#include <filesystem>

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

void ConfigNode::finish() const {
  if (node_ && node_.IsMap()) {
    for (const auto& kv : node_) {
      // A key that is not a scalar (a sequence or mapping used as a key) is never a known setting.
      if (!kv.first.IsScalar())
        fail(YAML::Dump(kv.first), "is not a known setting (keys must be plain names)");
      const std::string key = kv.first.Scalar();
      if (known_.count(key) == 0) fail(key, "is not a known setting (typo?)");
    }
  }
}

void ConfigNode::fail(const std::string& key, const std::string& problem) const {
  const std::string full = path_.empty() ? key : path_ + "." + key;
  throw ConfigError(file_ + ": key '" + full + "' " + problem);
}

}  // namespace glmbslam
