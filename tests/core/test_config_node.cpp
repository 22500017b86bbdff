#include <gtest/gtest.h>

#include "core/config_node.hpp"

namespace glmbslam {
namespace {

TEST(ConfigNode, ReadsValuesAndKeepsDefaults) {
  auto node = ConfigNode::parse("a: 2\nb: hello\n", "test.yaml");
  int a = 1;
  std::string b = "x";
  double c = 0.5;
  node.read("a", a);
  node.read("b", b);
  node.read("c", c);
  node.finish();
  EXPECT_EQ(a, 2);
  EXPECT_EQ(b, "hello");
  EXPECT_EQ(c, 0.5);
}

TEST(ConfigNode, UnknownKeyIsAnErrorNamingKeyAndFile) {
  auto node = ConfigNode::parse("a: 2\ntypo: 3\n", "cfg.yaml");
  int a = 0;
  node.read("a", a);
  try {
    node.finish();
    FAIL() << "expected ConfigError";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("typo"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("cfg.yaml"), std::string::npos);
  }
}

TEST(ConfigNode, UnknownKeySuggestsTheClosestKnownOneOrListsThem) {
  auto message = [](const std::string& yaml) {
    auto node = ConfigNode::parse(yaml, "cfg.yaml");
    int v = 0;
    node.read("particles", v);
    node.read("seed", v);
    try {
      node.finish();
    } catch (const ConfigError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(message("particels: 5\n"),
            "cfg.yaml: key 'particels' is not a known setting (did you mean 'particles'?)");
  EXPECT_EQ(message("sed: 1\n"), "cfg.yaml: key 'sed' is not a known setting (did you mean 'seed'?)");
  EXPECT_EQ(message("mlslam: {}\n"),
            "cfg.yaml: key 'mlslam' is not a known setting (known here: particles, seed)");
}

TEST(ConfigNode, WrongTypeIsAnError) {
  auto node = ConfigNode::parse("a: [1, 2]\n", "cfg.yaml");
  int a = 0;
  EXPECT_THROW(node.read("a", a), ConfigError);
}

TEST(ConfigNode, NestedKeysAreNamedWithTheirPath) {
  auto node = ConfigNode::parse("outer:\n  inner: 1\n  bad: 2\n", "cfg.yaml");
  auto child = node.child("outer");
  int inner = 0;
  child.read("inner", inner);
  node.finish();
  try {
    child.finish();
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("outer.bad"), std::string::npos);
  }
}

TEST(ConfigNode, RangeAndChoiceChecks) {
  auto node = ConfigNode::parse("p: 1.5\nmode: fast\n", "cfg.yaml");
  double p = 0.5;
  EXPECT_THROW(node.read_in_range("p", p, 0.0, 1.0), ConfigError);
  std::string mode = "slow";
  EXPECT_THROW(node.read_choice("mode", mode, {"slow", "exact"}), ConfigError);
}

}  // namespace
}  // namespace glmbslam

namespace glmbslam {
namespace {

// Found by fuzz_config: a key that is a sequence or a mapping ended the program with a yaml-cpp conversion
// error instead of the ConfigError naming the key.
TEST(ConfigNode, NonScalarKeyIsAConfigError) {
  for (const char* text : {"? [a, b]\n: 1\n", "? {a: 1}\n: 2\n"}) {
    ConfigNode node = ConfigNode::parse(text, "fuzz.yaml");
    EXPECT_THROW(node.finish(), ConfigError) << text;
  }
}

}  // namespace
}  // namespace glmbslam
