#include "adapters/deployment.h"

#include <arpa/inet.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>

#include "adapters/device/device_config.h"

namespace fs = std::filesystem;

namespace hcosim::adapters {

namespace {

ServiceSpec parse_service(const Config& c) {
  const std::string& file = c.file();
  const YAML::Node& node = c.node();
  if (!node.IsMap()) c.fail("", "each service must be a map with name, kind and rate");
  c.allow_only(keys::kService);
  c.require({"name", "kind", "rate"}, "service");
  ServiceSpec s;
  s.line = node.Mark().line + 1;
  s.where = c.where();
  s.name = c.string("name", "");
  if (!std::regex_match(s.name, std::regex("[a-z][a-z0-9_]{0,30}")))
    c.fail("name", "service name '" + s.name + "' must be 1 to 31 of a-z, 0-9, _ and start with a letter");
  s.kind = c.string("kind", "");
  if (!std::regex_match(s.kind, std::regex("[a-z][a-z0-9_]*")))
    c.fail("kind", "service kind '" + s.kind + "' must be a-z, 0-9 and _");
  s.rate_hz = c.number("rate", 0, -1e300, 1e300);
  if (s.rate_hz <= 0 || s.rate_hz > 1e5) c.fail("rate", "'rate' must be in (0, 100000] Hz");
  if (c.has("on_failure")) {
    s.where = c.where("on_failure");
    const std::string v = c.text("on_failure", "stop_all", {"stop_all", "restart", "ignore"});
    s.on_failure = v == "restart" ? OnFailure::kRestart : v == "ignore" ? OnFailure::kIgnore : OnFailure::kStopAll;
  }
  // The kinds whose threads answer the hand come first by default.
  if (s.kind == "haptic" || s.kind == "rigid" || s.kind == "deformable") s.priority = kHapticPriority;
  s.priority = c.whole("priority", s.priority, 0, 99);
  s.cpu = c.whole("cpu", s.cpu, 0, 1023);
  s.params = c.map("params").node();
  s.host = c.string("host", "");
  if (c.has("objects")) {
    const YAML::Node n = node["objects"];
    if (!n.IsSequence()) c.fail("objects", "'objects' must be a list of scene object names");
    for (const YAML::Node& o : n) {
      if (!o.IsScalar()) throw adapters::config_error(file, o, "'objects' must be a list of scene object names");
      s.objects.push_back(o.Scalar());
    }
  }
  return s;
}

// The hosts: list. A host has a name and its address or interface, not
// both; one host (the first unless one says `clock: on`) runs the
// lockstep clock. Two hosts cannot share an address.
void parse_hosts(const Config& root, Deployment& d) {
  const YAML::Node n = root.node()["hosts"];
  if (!n.IsSequence() || n.size() == 0)
    root.fail("hosts", "'hosts' must be a list of {name, address or interface} (docs/deployment.md)");
  std::map<std::string, std::string> address_of;  // address -> where
  std::string clock_where;                        // of the host that says clock: on
  for (const Config& h : root.list("hosts")) {
    if (!h.node().IsMap()) h.fail("", "each host must be a map with name and address or interface");
    h.allow_only(keys::kHost);
    h.require({"name"}, "host");
    Host host;
    host.name = h.string("name", "");
    host.where = h.where();
    if (!std::regex_match(host.name, std::regex("[a-z][a-z0-9_]{0,30}")))
      h.fail("name", "host name '" + host.name + "' must be 1 to 31 of a-z, 0-9, _ and start with a letter");
    for (const Host& other : d.hosts)
      if (other.name == host.name)
        h.fail("name", "host '" + host.name + "' is defined twice (first at " + other.where + ")");
    if (h.has("address") == h.has("interface"))
      h.fail("", "host '" + host.name + "' needs its address or its interface (one of them)");
    if (h.has("address")) {
      host.address = h.string("address", "");
      in_addr parsed{};
      if (inet_pton(AF_INET, host.address.c_str(), &parsed) != 1)
        h.fail("address", "'" + host.address + "' is not an IPv4 address (a.b.c.d)");
      const auto [it, fresh] = address_of.emplace(host.address, h.where("address"));
      if (!fresh) h.fail("address", "address " + host.address + " is another host's too (" + it->second + ")");
    } else {
      host.interface = h.string("interface", "");
      if (!std::regex_match(host.interface, std::regex("[A-Za-z0-9_.-]{1,15}")))
        h.fail("interface",
               "'" + host.interface + "' is not a network interface name (1 to 15 of A-Z, a-z, 0-9, _ . -)");
    }
    if (h.on("clock", false)) {
      if (!clock_where.empty())
        h.fail("clock",
               "host '" + d.clock_host + "' runs the lockstep clock already (" + clock_where + "): one host does");
      d.clock_host = host.name;
      clock_where = h.where("clock");
    }
    d.hosts.push_back(std::move(host));
  }
  if (d.clock_host.empty()) d.clock_host = d.hosts.front().name;
}

// The network section: it needs hosts, peers need every host's address,
// a discovery server a host with an address.
void parse_network(const Config& root, Deployment& d) {
  if (!root.node()["network"].IsMap()) root.fail("network", "'network' must be a map (docs/deployment.md)");
  const Config n = root.map("network");
  n.allow_only(keys::kNetwork);
  if (d.hosts.empty()) root.fail("network", "'network' is for a rig of several hosts: the file has no hosts: list");
  NetworkSpec& net = d.network;
  net.defined = true;
  net.discovery = n.text("discovery", net.discovery, {"multicast", "peers", "server"});
  net.udp_only = n.text("transport", "shm_udp", {"shm_udp", "udp"}) == "udp";
  net.socket_buffer_kib = n.whole("socket_buffer_kib", net.socket_buffer_kib, 0, 1 << 20);
  net.bulk_mbit = n.number("bulk_mbit", net.bulk_mbit, 0, 100000);
  net.server_port = n.whole("server_port", net.server_port, 1024, 65535);
  if (n.has("server") && net.discovery != "server") n.fail("server", "'server' goes with discovery: server");
  if (net.discovery == "server") {
    net.server = n.string("server", d.clock_host);
    const auto it = std::find_if(d.hosts.begin(), d.hosts.end(), [&](const Host& h) { return h.name == net.server; });
    if (it == d.hosts.end()) n.fail("server", "no host '" + net.server + "' in hosts:");
    if (it->address.empty())
      n.fail(n.has("server") ? "server" : "discovery",
             "the discovery server's host '" + net.server + "' needs an address (" + it->where + ")");
  }
  if (net.discovery == "peers")
    for (const Host& h : d.hosts)
      if (h.address.empty())
        throw ConfigError(h.where + ": discovery: peers (" + n.where("discovery") + ") needs every host's address; '" +
                          h.name + "' gives an interface");
}

// The hosts' names, for errors: "a, b".
std::string host_names(const Deployment& d) {
  std::string names;
  for (const Host& h : d.hosts) names += (names.empty() ? "" : ", ") + h.name;
  return names;
}

bool has_host(const Deployment& d, const std::string& name) {
  return std::any_of(d.hosts.begin(), d.hosts.end(), [&](const Host& h) { return h.name == name; });
}

// Every service is on one of the hosts when the file has hosts, and names
// none when it has not.
void check_placement(const Config& root, const Deployment& d) {
  const YAML::Node list = root.node()["services"];
  for (std::size_t i = 0; i < d.services.size(); ++i) {
    const ServiceSpec& s = d.services[i];
    const Config entry(root.file(), list[i]);
    if (d.hosts.empty()) {
      if (entry.has("host"))
        entry.fail("host",
                   "service '" + s.name + "' names a host, but the file has no hosts: list (docs/deployment.md)");
      continue;
    }
    if (!entry.has("host"))
      entry.fail("", "service '" + s.name + "' is on no host: say host: NAME, one of the hosts at " + d.hosts_where);
    if (!has_host(d, s.host)) entry.fail("host", "no host '" + s.host + "' in hosts: (" + host_names(d) + ")");
  }
}

// The scene's objects and camera for one service, added to its params
// unless they give their own: deformable and rigid services get the
// scene's objects of their kind (as `objects` and `bodies`), the tracker
// the camera, the AR view every object (kind kept). The marker is no
// service's params: each reader takes it typed. A service with nothing to
// serve is marked unneeded.
void add_scene(const std::string& file, const Scene& scene, ServiceSpec& s, const YAML::Node& entry) {
  for (std::size_t i = 0; i < s.objects.size(); ++i) {
    bool found = false;
    for (const YAML::Node& o : scene.objects) found = found || o["name"].Scalar() == s.objects[i];
    if (!found) throw config_error(file, entry["objects"][i], "no object '" + s.objects[i] + "' in the scene");
  }
  // The scene's part is added to the params node itself, which keeps its
  // place in the file for errors about it.
  YAML::Node params = s.params;
  const bool own_params = params.size() > 0;
  // kind "": every object, each keeping its kind.
  const auto objects_of = [&](const std::string& kind) {
    YAML::Node list(YAML::NodeType::Sequence);
    for (const YAML::Node& o : scene.objects) {
      const std::string name = o["name"].Scalar();
      if (!kind.empty() && o["kind"].Scalar() != kind) continue;
      if (!s.objects.empty() && std::find(s.objects.begin(), s.objects.end(), name) == s.objects.end()) continue;
      // Keys are inserted as the file's nodes, so that a service's error
      // about one (an unknown key) still names its line.
      YAML::Node copy(YAML::NodeType::Map);
      for (const auto& kv : o)
        if (kv.first.Scalar() != "kind" || kind.empty()) copy.force_insert(kv.first, kv.second);
      list.push_back(copy);
    }
    return list;
  };
  if (s.kind == "deformable" || s.kind == "rigid") {
    const char* key = s.kind == "rigid" ? "bodies" : "objects";
    if (!params[key]) {
      const YAML::Node list = objects_of(s.kind);
      if (list.size() == 0 && scene.defined)
        s.unneeded = "the scene has no " + s.kind + " object";
      else
        params[key] = list;
    }
  } else if (s.kind == "tracker") {
    // An absent camera is a null node, which converts to true: ask IsMap.
    if (scene.camera.IsMap())
      for (const auto& kv : scene.camera)
        if (!params[kv.first.Scalar()]) params[kv.first.Scalar()] = kv.second;
    if (!scene.camera.IsMap() && !own_params && scene.defined) s.unneeded = "the scene has no camera";
  } else if (s.kind == "ar_view") {
    if (!params["objects"]) params["objects"] = objects_of("");
    if (!scene.camera.IsMap() && !own_params && scene.defined) s.unneeded = "the scene has no camera";
  }
  if (!s.objects.empty() && s.kind != "deformable" && s.kind != "rigid")
    throw config_error(file, entry["objects"], "only deformable and rigid services serve scene objects");
}

}  // namespace

const char* to_string(Mode m) { return m == Mode::kLockstep ? "lockstep" : "realtime"; }

const char* to_string(OnFailure f) {
  return f == OnFailure::kRestart ? "restart" : f == OnFailure::kIgnore ? "ignore" : "stop_all";
}

bool observes(const ServiceSpec& s) { return s.kind == "foxglove"; }

void check_policy(const ServiceSpec& s, Mode mode) {
  if (mode == Mode::kLockstep && s.on_failure != OnFailure::kStopAll && !observes(s))
    throw ConfigError(s.where + ": on_failure: " + to_string(s.on_failure) +
                      " needs mode realtime (in lockstep the "
                      "clock waits on every follower at every step: one cannot be missing or rejoin)");
}

Mode parse_mode(const std::string& s) {
  if (s == "realtime") return Mode::kRealtime;
  if (s == "lockstep") return Mode::kLockstep;
  throw std::invalid_argument("mode must be 'realtime' or 'lockstep', not '" + s + "'");
}

namespace {

// A haptic service's `tip_radius` is its stylus's: every rigid and
// deformable service serving that device's contacts gets it, unless its
// params give their own. Checked here, so that a bad one is named at its
// line before anything starts.
void give_tip_radius(const std::string& file, Deployment& d) {
  for (const ServiceSpec& device : d.services) {
    if (device.kind != "haptic" || !device.params["tip_radius"]) continue;
    adapters::Config(file, device.params).number("tip_radius", 0, 0, device::kMaxTipRadius);
    for (ServiceSpec& s : d.services) {
      if (s.kind != "rigid" && s.kind != "deformable") continue;
      const YAML::Node dev = s.params["device"];
      if ((dev && dev.IsScalar() ? dev.Scalar() : std::string(adapters::device::kDefaultDevice)) != device.name)
        continue;
      YAML::Node params = s.params;
      if (!params["tip_radius"]) params["tip_radius"] = device.params["tip_radius"];
    }
  }
}

}  // namespace

std::vector<ForceSource> force_sources(const Deployment& d, const std::string& device) {
  std::vector<ForceSource> out;
  for (const ServiceSpec& s : d.services) {
    if (!s.unneeded.empty() || (s.kind != "rigid" && s.kind != "deformable")) continue;
    const YAML::Node dev = s.params["device"];
    if ((dev && dev.IsScalar() ? dev.Scalar() : std::string(adapters::device::kDefaultDevice)) != device) continue;
    const YAML::Node list = s.params[s.kind == "rigid" ? "bodies" : "objects"];
    if (!list || !list.IsSequence()) continue;
    for (const YAML::Node& o : list)
      if (o.IsMap() && o["name"] && o["name"].IsScalar()) out.push_back({o["name"].Scalar(), s.name, s.rate_hz});
  }
  return out;
}

Deployment load_deployment(const std::string& path) {
  const Config root = Config::load(path, "a deployment");
  root.allow_only(keys::kDeployment);

  Deployment d;
  d.file = path;
  d.services_where = d.hosts_where = path + ":1:1";
  d.domain = root.whole("domain", d.domain, 0, kMaxDomain);
  d.mode = parse_mode(root.text("mode", to_string(d.mode), {"realtime", "lockstep"}));
  d.step_s = root.number("step", d.step_s, 1e-6, 1);
  d.duration_s = root.number("duration", d.duration_s, 0, 1e9);
  if (root.has("security")) {
    const std::string what = "'security' must be a map with 'dir' (docs/security.md)";
    if (!root.node()["security"].IsMap()) root.fail("security", what);
    const Config sec = root.map("security");
    sec.allow_only(keys::kSecurity);
    if (!sec.has("dir")) root.fail("security", what);
    fs::path dir = sec.string("dir", "");
    if (dir.empty()) sec.fail("dir", "'dir' must name a folder");
    if (dir.is_relative()) dir = fs::path(path).parent_path() / dir;
    d.security = dir.lexically_normal().string();
    d.security_where = root.where("security");
  }
  if (root.has("hosts")) {
    d.hosts_where = root.where("hosts");
    parse_hosts(root, d);
  }
  if (root.has("network")) parse_network(root, d);
  if (root.has("scene")) d.scene = scene_config(Config(path, root.node()["scene"]));
  if (root.has("services")) {
    const YAML::Node n = root.node()["services"];
    if (!n.IsSequence()) root.fail("services", "'services' must be a list");
    d.services_where = root.where("services");
    std::set<std::string> names;
    for (const YAML::Node& s : n) {
      const Config entry(path, s);
      ServiceSpec spec = parse_service(entry);
      if (spec.name == "clock") entry.fail("name", "the name 'clock' is reserved for the lockstep master");
      if (!names.insert(spec.name).second) entry.fail("name", "service name '" + spec.name + "' is used twice");
      check_policy(spec, d.mode);
      add_scene(path, d.scene, spec, s);
      d.services.push_back(std::move(spec));
    }
    give_tip_radius(path, d);
  }
  check_placement(root, d);
  return d;
}

std::vector<const ServiceSpec*> services_on(const Deployment& d, const std::string& host) {
  if (d.hosts.empty())
    throw ConfigError(d.hosts_where + ": --host " + host + ": the deployment has no hosts: list (docs/deployment.md)");
  if (!has_host(d, host))
    throw ConfigError(d.hosts_where + ": --host " + host + ": no such host in hosts: (" + host_names(d) + ")");
  std::vector<const ServiceSpec*> out;
  for (const ServiceSpec& s : d.services)
    if (s.host == host) out.push_back(&s);
  return out;
}

}  // namespace hcosim::adapters
