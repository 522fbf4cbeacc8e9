#include "adapters/config.h"

#include <gtest/gtest.h>

#include "tests/support/temp_dir.h"

namespace hcosim::adapters {
namespace {

using tests::message_of;

// The text's root map, as the file "f.yaml".
Config parse(const std::string& text) { return Config::parse(text, "f.yaml", "a test file"); }

TEST(Config, RangeAndChoiceErrorsAreLocated) {
  const Config p = parse("gain: 7\nrole: boss\nn: 3\nx: 0.5\n");
  EXPECT_EQ(p.number("absent", 1.5, 0, 2), 1.5);
  EXPECT_EQ(message_of<ConfigError>([&] { p.number("gain", 0, 0, 5); }), "f.yaml:1:7: 'gain' = 7 is outside [0, 5]");
  EXPECT_EQ(message_of<ConfigError>([&] {
              p.text("role", "a", {"a", "b"});
            }),
            "f.yaml:2:7: 'role' must be one of a, b, not 'boss'");
  EXPECT_EQ(p.whole("n", 0, 0, 5), 3);
  EXPECT_EQ(p.whole("absent", 4, 0, 5), 4);
  EXPECT_EQ(message_of<ConfigError>([&] { p.whole("n", 0, 0, 2); }),
            "f.yaml:3:4: 'n' must be a whole number from 0 to 2, not 3");
  EXPECT_EQ(message_of<ConfigError>([&] { p.whole("x", 0, 0, 2); }),
            "f.yaml:4:4: 'x' must be a whole number from 0 to 2, not 0.5");
  EXPECT_EQ(message_of<ConfigError>([&] { p.number("role", 0, 0, 1); }),
            "f.yaml:2:7: 'role' must be a number, not 'boss'");
}

TEST(Config, NonFiniteNumbersAreRefused) {
  const Config p = parse("a: .nan\nb: .inf\nc: [1, .nan, 2]\n");
  EXPECT_EQ(message_of<ConfigError>([&] { p.number("a", 0, -1e9, 1e9); }), "f.yaml:1:4: 'a' must be a finite number");
  EXPECT_EQ(message_of<ConfigError>([&] { p.number("b", 0, -1e9, 1e9); }), "f.yaml:2:4: 'b' must be a finite number");
  EXPECT_EQ(message_of<ConfigError>([&] { p.numbers("c", 0, 5); }), "f.yaml:3:8: 'c' must be a finite number");
}

TEST(Config, UnknownKeysNameTheClosestValidOne) {
  const Config p = parse("gain: 1\nrte: 5\n");
  EXPECT_NO_THROW(p.allow_only({"gain", "rte"}));
  EXPECT_EQ(message_of<ConfigError>([&] {
              p.allow_only({"gain", "rate"});
            }),
            "f.yaml:2:1: unknown key 'rte'; did you mean 'rate'?");
  EXPECT_EQ(message_of<ConfigError>([&] {
              p.allow_only({"gain", "speed"});
            }),
            "f.yaml:2:1: unknown key 'rte' (valid keys: gain, speed)");
  EXPECT_EQ(message_of<ConfigError>([&] {
              p.require({"gain", "kind"}, "service");
            }),
            "f.yaml:1:1: service is missing required key 'kind'");
}

// A file written back by a YAML library says true and false.
TEST(Config, SwitchesTakeOnOffTrueAndFalse) {
  const Config p = parse("a: on\nb: off\nc: true\nd: false\ne: yes\n");
  EXPECT_TRUE(p.on("a", false));
  EXPECT_FALSE(p.on("b", true));
  EXPECT_TRUE(p.on("c", false));
  EXPECT_FALSE(p.on("d", true));
  EXPECT_TRUE(p.on("absent", true));
  EXPECT_EQ(message_of<ConfigError>([&] { p.on("e", true); }),
            "f.yaml:5:4: 'e' must be on or off (or true or false), not 'yes'");
}

TEST(Config, MapsListsAndVectorsAreReadWithLocatedErrors) {
  const Config p = parse(
      "orbit: {distance: 0.3}\nat: [1, 2.5]\nbad: [1, x]\nfar: [1, 9]\nflat: 3\nitems: [{a: 1}, 2]\n"
      "v: [1, 2]\n");
  EXPECT_EQ(p.map("orbit").number("distance", 0, 0, 1), 0.3);
  EXPECT_EQ(p.map("absent").number("distance", 0.5, 0, 1), 0.5);
  EXPECT_EQ(p.numbers("at", 0, 5), (std::vector<double>{1, 2.5}));
  EXPECT_TRUE(p.numbers("absent", 0, 5).empty());
  EXPECT_EQ(message_of<ConfigError>([&] { p.numbers("bad", 0, 5); }), "f.yaml:3:10: 'bad' must be a number, not 'x'");
  EXPECT_EQ(message_of<ConfigError>([&] { p.numbers("far", 0, 5); }),
            "f.yaml:4:10: an entry of 'far', 9, is outside [0, 5]");
  EXPECT_EQ(message_of<ConfigError>([&] { p.numbers("flat", 0, 5); }), "f.yaml:5:7: 'flat' must be a list of numbers");
  EXPECT_EQ(message_of<ConfigError>([&] { p.map("flat"); }), "f.yaml:5:7: 'flat' must be a map of keys");
  EXPECT_EQ(message_of<ConfigError>([&] { p.list("items"); }),
            "f.yaml:6:17: each entry of 'items' must be a map of keys");
  EXPECT_EQ(message_of<ConfigError>([&] { p.vec3("v", {0, 0, 0}); }), "f.yaml:7:4: 'v' must be [x, y, z]");
  EXPECT_EQ(p.vec3("absent", {1, 2, 3}), (std::array<double, 3>{1, 2, 3}));
  EXPECT_EQ(p.where("far"), "f.yaml:4:6");
  EXPECT_EQ(p.where(), "f.yaml:1:1");
}

TEST(Config, PathsAreTakenFromTheFilesFolder) {
  tests::TempDir dir;
  const Config p = Config::parse("in: here.txt\nout: sub/there.txt\nabs: /nonexistent/x\n",
                                 (dir.path / "f.yaml").string(), "a test file");
  EXPECT_EQ(message_of<ConfigError>([&] { p.path("in"); }),
            (dir.path / "f.yaml").string() + ":1:5: 'in': no file " + (dir.path / "here.txt").string());
  std::ofstream(dir.path / "here.txt") << "x";
  EXPECT_EQ(p.path("in"), (dir.path / "here.txt").string());
  EXPECT_EQ(p.output_path("out"), (dir.path / "sub/there.txt").string());
  EXPECT_EQ(p.output_path("abs"), "/nonexistent/x");
  EXPECT_EQ(p.path("absent"), "");
}

TEST(Config, FilesThatAreNotMapsOrNotYamlAreNamed) {
  EXPECT_EQ(message_of<ConfigError>([] { Config::load("/nonexistent/f.yaml", "a deployment"); }),
            "/nonexistent/f.yaml: cannot be read");
  EXPECT_EQ(message_of<ConfigError>([] { parse("- 1\n- 2\n"); }), "f.yaml:1:1: a test file must be a YAML map");
  EXPECT_EQ(message_of<ConfigError>([] { parse("a: [1, 2\n"); }).rfind("f.yaml:2:1: YAML syntax error: ", 0), 0u);
}

}  // namespace
}  // namespace hcosim::adapters
