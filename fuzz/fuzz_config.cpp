// The YAML config loader: ConfigNode (typed reads, unknown-key checks) through the stereo config
// (app::parse_stereo_config: every section and key of config/kitti*.yaml).
#include <yaml-cpp/yaml.h>

#include "app/stereo_config.hpp"
#include "core/config_node.hpp"
#include "fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace glmbslam;
  const std::string text(reinterpret_cast<const char*>(data), size);
  fuzz::expect_clean_rejection([&] { ConfigNode::parse(text, "fuzz.yaml"); });
  const std::string path = fuzz::write_text("config.yaml", text);
  fuzz::expect_clean_rejection([&] { ConfigNode::load_file(path); });
  fuzz::expect_clean_rejection([&] {
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw InputError("fuzz.yaml", e.what());  // what the run command does with a YAML syntax error
    }
    if (root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
    app::parse_stereo_config(root, "fuzz.yaml");
  });
  return 0;
}
