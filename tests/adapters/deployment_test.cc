#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "adapters/deployment.h"
#include "tests/support/doc_keys.h"
#include "tests/support/temp_dir.h"

namespace hcosim::adapters {
namespace {

// `text` as `name` in this process's folder of files, removed at its exit.
std::string write_file(const std::string& name, const std::string& text) {
  static const struct Folder {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("hcosim_deployment_test_" + std::to_string(getpid()));
    Folder() { std::filesystem::create_directories(path); }
    ~Folder() { std::filesystem::remove_all(path); }
  } folder;
  const auto path = folder.path / name;
  std::ofstream(path) << text;
  return path.string();
}

TEST(Deployment, ParsesAValidFile) {
  const std::string f = write_file("ok.yaml",
                                   "domain: 12\nmode: lockstep\nstep: 0.001\nduration: 2\nservices:\n"
                                   "  - name: haptic\n    kind: haptic_device\n    rate: 1000\n"
                                   "  - name: view\n    kind: ar_view\n    rate: 30\n    params: {fps: 30}\n");
  const Deployment d = load_deployment(f);
  EXPECT_EQ(d.domain, 12);
  EXPECT_EQ(d.mode, Mode::kLockstep);
  EXPECT_DOUBLE_EQ(d.duration_s, 2);
  ASSERT_EQ(d.services.size(), 2u);
  EXPECT_EQ(d.services[1].kind, "ar_view");
  EXPECT_EQ(d.services[1].line, 9);
  EXPECT_EQ(adapters::Config(f, d.services[1].params).number("fps", 0, 1, 120), 30);
}

TEST(Deployment, DefaultsWhenKeysAreAbsent) {
  const Deployment d = load_deployment(write_file("empty.yaml", "services: []\n"));
  EXPECT_EQ(d.domain, 0);
  EXPECT_EQ(d.mode, Mode::kRealtime);
  EXPECT_DOUBLE_EQ(d.step_s, 0.001);
  EXPECT_TRUE(d.services.empty());
}

struct BadCase {
  const char* name;
  const char* text;
  const char* where;  // expected ":LINE:COL: " after the file name
  const char* what;   // expected part of the message
};

class BadDeployment : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadDeployment, NamesFileLineColumnAndProblem) {
  const BadCase& c = GetParam();
  const std::string f = write_file(std::string(c.name) + ".yaml", c.text);
  try {
    load_deployment(f);
    FAIL() << "no error for " << c.name;
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(f + c.where, 0), 0u) << msg;
    EXPECT_NE(msg.find(c.what), std::string::npos) << msg;
  }
}

INSTANTIATE_TEST_SUITE_P(
    Table, BadDeployment,
    ::testing::Values(
        BadCase{"syntax", "domain: 1\nservices: [\n", ":3:1: ", "YAML syntax error"},
        BadCase{"typo", "domian: 3\n", ":1:1: ", "did you mean 'domain'?"},
        BadCase{"unknown", "frobnicate: 3\n", ":1:1: ", "unknown key 'frobnicate' (valid keys:"},
        BadCase{"domain_range", "domain: 233\n", ":1:9: ", "whole number from 0 to 232, not 233"},
        BadCase{"domain_type", "domain: abc\n", ":1:9: ", "must be a number"},
        BadCase{"mode", "mode: fast\n", ":1:7: ", "'mode' must be one of realtime, lockstep, not 'fast'"},
        BadCase{"step", "step: 0\n", ":1:7: ", "'step' = 0 is outside [1e-06, 1]"},
        BadCase{"services_type", "services: 3\n", ":1:11: ", "must be a list"},
        BadCase{"missing_kind", "services:\n  - name: a\n    rate: 10\n", ":2:5: ", "missing required key 'kind'"},
        BadCase{"negative_rate", "services:\n  - {name: a, kind: b, rate: -5}\n", ":2:30: ", "'rate' must be in"},
        BadCase{"service_typo", "services:\n  - {name: a, kind: b, rte: 5}\n", ":2:24: ", "did you mean 'rate'?"},
        BadCase{"bad_name", "services:\n  - {name: Bad-Name, kind: b, rate: 5}\n", ":2:12: ", "must be 1 to 31"},
        BadCase{"duplicate", "services:\n  - {name: a, kind: b, rate: 5}\n  - {name: a, kind: b, rate: 5}\n",
                ":3:12: ", "used twice"},
        BadCase{"reserved", "services:\n  - {name: clock, kind: b, rate: 5}\n", ":2:12: ", "reserved"},
        BadCase{"on_failure", "services:\n  - {name: a, kind: b, rate: 5, on_failure: retry}\n",
                ":2:45: ", "must be one of stop_all, restart, ignore, not 'retry'"},
        BadCase{"restart_lockstep", "mode: lockstep\nservices:\n  - {name: a, kind: b, rate: 5, on_failure: restart}\n",
                ":3:45: ", "needs mode realtime"},
        BadCase{"scene_key", "scene:\n  objekts: []\n", ":2:3: ", "did you mean 'objects'?"},
        BadCase{"scene_kind", "scene:\n  objects:\n    - {name: a, kind: fluid}\n", ":3:23: ", "rigid or deformable"},
        BadCase{"scene_twice", "scene:\n  objects:\n    - {name: a, kind: rigid}\n    - {name: a, kind: rigid}\n",
                ":4:14: ", "defined twice"},
        BadCase{"scene_no_kind", "scene:\n  objects:\n    - {name: a}\n", ":3:7: ", "missing required key 'kind'"},
        BadCase{"security_type", "security: keys\n", ":1:11: ", "a map with 'dir'"},
        BadCase{"security_key", "security: {dri: keys}\n", ":1:12: ", "did you mean 'dir'?"},
        BadCase{"security_empty", "security: {dir: ''}\n", ":1:17: ", "'dir' must name a folder"},
        BadCase{"priority", "services:\n  - {name: a, kind: b, rate: 5, priority: 100}\n",
                ":2:43: ", "'priority' must be a whole number from 0 to 99"},
        BadCase{"cpu", "services:\n  - {name: a, kind: b, rate: 5, cpu: 0.5}\n",
                ":2:38: ", "'cpu' must be a whole number"},
        BadCase{"hosts_type", "hosts: 3\n", ":1:8: ", "'hosts' must be a list"},
        BadCase{"host_key", "hosts:\n  - {name: a, adress: 10.0.0.1}\n", ":2:15: ", "did you mean 'address'?"},
        BadCase{"host_nowhere", "hosts:\n  - {name: a}\n", ":2:5: ", "needs its address or its interface"},
        BadCase{"host_both", "hosts:\n  - {name: a, address: 10.0.0.1, interface: eth0}\n",
                ":2:5: ", "needs its address or its interface"},
        BadCase{"host_address", "hosts:\n  - {name: a, address: 10.0.0}\n", ":2:24: ", "not an IPv4 address"},
        BadCase{"host_interface", "hosts:\n  - {name: a, interface: 'eth 0'}\n",
                ":2:26: ", "not a network interface name"},
        BadCase{"host_name", "hosts:\n  - {name: Rig, address: 10.0.0.1}\n", ":2:12: ", "host name 'Rig' must be"},
        BadCase{"host_twice", "hosts:\n  - {name: a, address: 10.0.0.1}\n  - {name: a, address: 10.0.0.2}\n",
                ":3:12: ", "defined twice (first at"},
        BadCase{"host_shared_address", "hosts:\n  - {name: a, address: 10.0.0.1}\n  - {name: b, address: 10.0.0.1}\n",
                ":3:24: ", "is another host's too ("},
        BadCase{"two_clocks",
                "hosts:\n  - {name: a, address: 10.0.0.1, clock: on}\n  - {name: b, address: 10.0.0.2, clock: on}\n",
                ":3:41: ", "runs the lockstep clock already"},
        BadCase{"unknown_host",
                "hosts:\n  - {name: a, address: 10.0.0.1}\nservices:\n  - {name: s, kind: b, rate: 5, host: x}\n",
                ":4:39: ", "no host 'x' in hosts: (a)"},
        BadCase{"no_host", "hosts:\n  - {name: a, address: 10.0.0.1}\nservices:\n  - {name: s, kind: b, rate: 5}\n",
                ":4:5: ", "is on no host"},
        BadCase{"host_without_hosts", "services:\n  - {name: s, kind: b, rate: 5, host: a}\n",
                ":2:39: ", "the file has no hosts"},
        BadCase{"network_without_hosts", "network: {discovery: peers}\n", ":1:10: ", "the file has no hosts: list"},
        BadCase{"network_discovery", "hosts:\n  - {name: a, address: 10.0.0.1}\nnetwork: {discovery: mdns}\n",
                ":3:22: ", "must be one of multicast, peers, server, not 'mdns'"},
        BadCase{"network_key", "hosts:\n  - {name: a, address: 10.0.0.1}\nnetwork: {discover: peers}\n",
                ":3:11: ", "did you mean 'discovery'?"},
        BadCase{"network_peers_interface", "hosts:\n  - {name: a, interface: eth1}\nnetwork: {discovery: peers}\n",
                ":2:5: ", "needs every host's address"},
        BadCase{"network_server_unknown",
                "hosts:\n  - {name: a, address: 10.0.0.1}\nnetwork: {discovery: server, server: x}\n",
                ":3:38: ", "no host 'x' in hosts:"},
        BadCase{"network_server_mode",
                "hosts:\n  - {name: a, address: 10.0.0.1}\nnetwork: {discovery: peers, server: a}\n",
                ":3:37: ", "'server' goes with discovery: server"},
        BadCase{"network_server_interface", "hosts:\n  - {name: a, interface: eth1}\nnetwork: {discovery: server}\n",
                ":3:22: ", "needs an address"},
        BadCase{"network_bulk_negative", "hosts:\n  - {name: a, address: 10.0.0.1}\nnetwork: {bulk_mbit: -2}\n",
                ":3:22: ", "bulk_mbit"},
        BadCase{"undefined_object",
                "scene:\n  objects: []\nservices:\n  - {name: a, kind: rigid, rate: 5, objects: [x]}\n",
                ":4:47: ", "no object 'x' in the scene"}),
    [](const auto& test) { return std::string(test.param.name); });

// One file for the rig: each host's services, the clock on the first host
// unless another says clock, and --host naming a host the file lacks.
TEST(Deployment, HostsPlaceEveryService) {
  const std::string f = write_file("rig.yaml", R"(hosts:
  - {name: device, address: 10.1.0.1}
  - {name: sim, interface: veth1}
services:
  - {name: omni, kind: haptic, rate: 1000, host: device}
  - {name: bodies, kind: rigid, rate: 1000, host: sim}
  - {name: objects, kind: deformable, rate: 1000, host: sim}
)");
  const Deployment d = load_deployment(f);
  ASSERT_EQ(d.hosts.size(), 2u);
  EXPECT_EQ(d.hosts[0].address, "10.1.0.1");
  EXPECT_EQ(d.hosts[1].interface, "veth1");
  EXPECT_EQ(d.clock_host, "device");
  std::vector<std::string> sim;
  for (const ServiceSpec* s : services_on(d, "sim")) sim.push_back(s->name);
  EXPECT_EQ(sim, (std::vector<std::string>{"bodies", "objects"}));
  try {
    services_on(d, "camera");
    FAIL() << "no error for a host the file lacks";
  } catch (const ConfigError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(f + ":2:3: --host camera: no such host in hosts: (device, sim)", 0), 0u)
        << e.what();
  }
  const std::string g = write_file("rig_clock.yaml", R"(hosts:
  - {name: device, address: 10.1.0.1}
  - {name: sim, address: 10.1.0.2, clock: on}
)");
  EXPECT_EQ(load_deployment(g).clock_host, "sim");
  EXPECT_THROW(services_on(load_deployment(write_file("one.yaml", "domain: 1\n")), "sim"), ConfigError);
}

// The haptic kinds come first unless the entry says otherwise; the
// device's sources are the objects of the services that name it.
TEST(Deployment, HapticKindsArePrioritisedAndTheirSourcesFound) {
  const Deployment d = load_deployment(write_file("loop.yaml", R"(scene:
  objects:
    - {name: box, kind: rigid, shape: cube}
    - {name: liver, kind: deformable, model: hybrid}
services:
  - {name: omni, kind: haptic, rate: 1000}
  - {name: bodies, kind: rigid, rate: 1000, cpu: 1}
  - {name: objects, kind: deformable, rate: 500, priority: 0, params: {device: omni}}
  - {name: other, kind: rigid, rate: 1000, objects: [box], params: {device: phantom}}
  - {name: cam, kind: tracker, rate: 30}
)"));
  ASSERT_EQ(d.services.size(), 5u);
  EXPECT_EQ(d.services[0].priority, kHapticPriority);
  EXPECT_EQ(d.services[1].priority, kHapticPriority);
  EXPECT_EQ(d.services[1].cpu, 1);
  EXPECT_EQ(d.services[2].priority, 0);
  EXPECT_EQ(d.services[4].priority, 0);
  EXPECT_EQ(d.services[4].cpu, -1);
  const std::vector<ForceSource> s = force_sources(d, "omni");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0].object, "box");
  EXPECT_EQ(s[0].service, "bodies");
  EXPECT_EQ(s[0].rate_hz, 1000);
  EXPECT_EQ(s[1].object, "liver");
  EXPECT_EQ(s[1].rate_hz, 500);
  ASSERT_EQ(force_sources(d, "phantom").size(), 1u);
  EXPECT_EQ(force_sources(d, "phantom")[0].service, "other");
}

TEST(Deployment, SecurityDirIsTakenFromTheFilesFolder) {
  const std::string f = write_file("secure.yaml", "security: {dir: ../keys}\n");
  const Deployment d = load_deployment(f);
  EXPECT_EQ(d.security, (std::filesystem::path(f).parent_path().parent_path() / "keys").string());
  EXPECT_EQ(d.security_where, f + ":1:11");
  EXPECT_EQ(load_deployment(write_file("abs.yaml", "security: {dir: /etc/keys}\n")).security, "/etc/keys");
  EXPECT_EQ(load_deployment(write_file("plain.yaml", "domain: 1\n")).security, "");
}

TEST(Deployment, MissingFileIsNamed) {
  try {
    load_deployment("/nonexistent/deploy.yaml");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/deploy.yaml: cannot be read");
  }
}

TEST(Deployment, TheArViewGetsEveryObject) {
  const std::string f = write_file("ar.yaml",
                                   "scene:\n  marker: {id: 7, size: 0.03}\n  camera: {source: synthetic}\n"
                                   "  objects:\n    - {name: box, kind: rigid, shape: cube, size: 0.01}\n"
                                   "    - {name: cube, kind: deformable, model: hybrid}\n"
                                   "services:\n  - {name: view, kind: ar_view, rate: 25}\n");
  const Deployment d = load_deployment(f);
  const adapters::Config p(f, d.services[0].params);
  EXPECT_TRUE(d.services[0].unneeded.empty());
  const std::vector<adapters::Config> objects = p.list("objects");
  ASSERT_EQ(objects.size(), 2u);
  EXPECT_EQ(objects[0].string("kind", ""), "rigid");
  EXPECT_EQ(objects[0].number("size", 0, 0, 1), 0.01);
  EXPECT_EQ(objects[1].string("name", ""), "cube");
  const Deployment no_camera = load_deployment(write_file(
      "ar2.yaml",
      "scene:\n  objects: [{name: box, kind: rigid}]\nservices:\n  - {name: view, kind: ar_view, rate: 25}\n"));
  EXPECT_EQ(no_camera.services[0].unneeded, "the scene has no camera");
}

// The marker is read once, typed; no service's params get its keys under
// other names (each reader takes the marker itself).
TEST(Deployment, TheMarkerIsTypedAndNoServicesParams) {
  const std::string f =
      write_file("plane.yaml",
                 "scene:\n  marker: {family: tag25h9, id: 7, size: 0.03, friction: 0.8}\n"
                 "  camera: {source: synthetic}\n"
                 "  objects: [{name: box, kind: rigid, shape: cube, size: 0.01}]\n"
                 "services:\n  - {name: bodies, kind: rigid, rate: 100}\n"
                 "  - {name: cam, kind: tracker, rate: 25}\n  - {name: view, kind: ar_view, rate: 25}\n");
  const Deployment d = load_deployment(f);
  EXPECT_EQ(d.scene.marker.family, "tag25h9");
  EXPECT_EQ(d.scene.marker.id, 7);
  EXPECT_EQ(d.scene.marker.size, 0.03);
  EXPECT_EQ(d.scene.marker.friction, 0.8);
  for (const ServiceSpec& s : d.services)
    for (const char* key : {"floor_friction", "family", "tag_size", "tag_id", "id", "size", "friction"})
      EXPECT_FALSE(s.params[key]) << s.name << " got '" << key << "'";
}

// The device's tip_radius reaches the services of its contacts (not
// those of another device, nor one that sets its own); a bad one is named
// at its line.
TEST(Deployment, TheDevicesTipRadiusReachesItsContactServices) {
  const std::string f =
      write_file("tip.yaml",
                 "scene:\n  objects: [{name: box, kind: rigid}, {name: cube, kind: deformable, model: hybrid}]\n"
                 "services:\n  - {name: omni, kind: haptic, rate: 1000, params: {script: s.yaml, tip_radius: 0.0015}}\n"
                 "  - {name: bodies, kind: rigid, rate: 1000}\n"
                 "  - {name: objects, kind: deformable, rate: 1000}\n"
                 "  - {name: own, kind: rigid, rate: 1000, params: {tip_radius: 0.001}}\n"
                 "  - {name: other, kind: rigid, rate: 1000, params: {device: left}}\n");
  const Deployment d = load_deployment(f);
  const auto tip = [&](int i) { return adapters::Config(f, d.services[i].params).number("tip_radius", -1, -1, 1); };
  EXPECT_EQ(tip(1), 0.0015);
  EXPECT_EQ(tip(2), 0.0015);
  EXPECT_EQ(tip(3), 0.001);
  EXPECT_EQ(tip(4), -1);
  const std::string e = tests::message_of<ConfigError>([] {
    load_deployment(
        write_file("bad_tip.yaml", "services:\n  - {name: omni, kind: haptic, rate: 1000, params: {tip_radius: 1}}\n"));
  });
  EXPECT_NE(e.find("bad_tip.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("'tip_radius' = 1 is outside [0, 0.01]"), std::string::npos) << e;
}

TEST(Deployment, AServicesErrorAboutASceneObjectNamesItsLine) {
  const std::string f = write_file("keys.yaml",
                                   "scene:\n  objects:\n    - {name: box, kind: rigid, size: 0.01}\n"
                                   "    - {name: ball, kind: rigid, colour: red}\n"
                                   "services:\n  - {name: bodies, kind: rigid, rate: 100}\n");
  const Deployment d = load_deployment(f);
  const std::vector<adapters::Config> bodies = adapters::Config(f, d.services[0].params).list("bodies");
  ASSERT_EQ(bodies.size(), 2u);
  std::string e = "no error";
  try {
    bodies[1].allow_only({"name", "size"});
  } catch (const ConfigError& x) {
    e = x.what();
  }
  EXPECT_NE(e.find("keys.yaml:4:33: unknown key 'colour'"), std::string::npos) << e;
}

// Every key the reader takes is in docs/deployment.md's table for its map,
// and every key there is one the reader takes.
TEST(Deployment, EachMapsKeysAreTheDocumentedOnes) {
  const std::pair<const char*, const std::vector<std::string>*> maps[] = {
      {"deployment", &keys::kDeployment}, {"security", &keys::kSecurity}, {"host", &keys::kHost},
      {"network", &keys::kNetwork},       {"scene", &keys::kScene},       {"marker", &keys::kMarker},
      {"service", &keys::kService}};
  for (const auto& [table, read] : maps)
    EXPECT_EQ(tests::documented_keys("deployment.md", table), tests::sorted(*read)) << "docs/deployment.md, " << table;
}

}  // namespace
}  // namespace hcosim::adapters
