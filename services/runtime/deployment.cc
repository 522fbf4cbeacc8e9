#include "services/runtime/deployment.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>

#include "services/runtime/participant.h"

namespace fs = std::filesystem;

namespace hcosim::services::runtime {

// The located YAML reading of adapters/config.h.
using adapters::config_number;
using adapters::config_text;
using adapters::join;
using adapters::load_yaml;
namespace {

ServiceSpec parse_service(const std::string& file, const YAML::Node& node) {
  if (!node.IsMap()) throw config_error(file, node, "each service must be a map with name, kind and rate");
  check_keys(file, node, {"name", "kind", "rate", "params", "on_failure", "objects", "priority", "cpu"});
  ServiceSpec s;
  s.line = node.Mark().line + 1;
  s.where = file + ":" + std::to_string(s.line) + ":" + std::to_string(node.Mark().column + 1);
  for (const char* key : {"name", "kind", "rate"})
    if (!node[key]) throw config_error(file, node, std::string("service is missing required key '") + key + "'");
  s.name = config_text(file, node["name"], "name");
  if (!std::regex_match(s.name, std::regex("[a-z][a-z0-9_]{0,30}")))
    throw config_error(file, node["name"],
                       "service name '" + s.name + "' must be 1 to 31 of a-z, 0-9, _ and start with a letter");
  s.kind = config_text(file, node["kind"], "kind");
  if (!std::regex_match(s.kind, std::regex("[a-z][a-z0-9_]*")))
    throw config_error(file, node["kind"], "service kind '" + s.kind + "' must be a-z, 0-9 and _");
  s.rate_hz = config_number(file, node["rate"], "rate");
  if (s.rate_hz <= 0 || s.rate_hz > 1e5) throw config_error(file, node["rate"], "'rate' must be in (0, 100000] Hz");
  if (const YAML::Node n = node["on_failure"]) {
    s.where = file + ":" + std::to_string(n.Mark().line + 1) + ":" + std::to_string(n.Mark().column + 1);
    const std::string v = config_text(file, n, "on_failure");
    if (v == "stop_all")
      s.on_failure = OnFailure::kStopAll;
    else if (v == "restart")
      s.on_failure = OnFailure::kRestart;
    else if (v == "ignore")
      s.on_failure = OnFailure::kIgnore;
    else
      throw config_error(file, n, "'on_failure' must be stop_all, restart or ignore, not '" + v + "'");
  }
  // The kinds whose threads answer the hand come first by default.
  if (s.kind == "haptic" || s.kind == "rigid" || s.kind == "deformable") s.priority = kHapticPriority;
  const auto whole = [&](const char* key, int lo, int hi, int& out) {
    const YAML::Node n = node[key];
    if (!n) return;
    const double v = config_number(file, n, key);
    if (v != std::floor(v) || v < lo || v > hi)
      throw config_error(
          file, n,
          std::string("'") + key + "' must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
    out = int(v);
  };
  whole("priority", 0, 99, s.priority);
  whole("cpu", 0, 1023, s.cpu);
  s.params = node["params"] ? node["params"] : YAML::Node(YAML::NodeType::Map);
  if (!s.params.IsMap()) throw config_error(file, node["params"], "'params' must be a map");
  if (const YAML::Node n = node["objects"]) {
    if (!n.IsSequence()) throw config_error(file, n, "'objects' must be a list of scene object names");
    for (const YAML::Node& o : n) s.objects.push_back(config_text(file, o, "objects"));
  }
  return s;
}

Scene parse_scene(const std::string& file, const YAML::Node& node) {
  if (!node.IsMap()) throw config_error(file, node, "'scene' must be a map of marker, camera and objects");
  check_keys(file, node, {"marker", "camera", "objects"});
  Scene scene;
  scene.defined = true;
  // yaml-cpp throws when a missing node is assigned: assign only present ones.
  if (const YAML::Node m = node["marker"]) {
    if (!m.IsMap()) throw config_error(file, m, "'marker' must be a map");
    check_keys(file, m, {"family", "id", "size"});
    scene.marker = m;
  }
  if (const YAML::Node c = node["camera"]) {
    if (!c.IsMap()) throw config_error(file, c, "'camera' must be a map of the tracker's params (docs/tracking.md)");
    scene.camera = c;
  }
  if (const YAML::Node list = node["objects"]) {
    if (!list.IsSequence()) throw config_error(file, list, "'objects' must be a list");
    std::set<std::string> names;
    for (const YAML::Node& o : list) {
      if (!o.IsMap()) throw config_error(file, o, "each scene object must be a map with name and kind");
      for (const char* key : {"name", "kind"})
        if (!o[key]) throw config_error(file, o, std::string("scene object is missing required key '") + key + "'");
      const std::string name = config_text(file, o["name"], "name");
      const std::string kind = config_text(file, o["kind"], "kind");
      if (kind != "rigid" && kind != "deformable")
        throw config_error(file, o["kind"], "scene object kind must be rigid or deformable, not '" + kind + "'");
      if (!names.insert(name).second)
        throw config_error(file, o["name"], "scene object '" + name + "' is defined twice");
      scene.objects.push_back(o);
    }
  }
  return scene;
}

// The scene's part for one service, added to its params unless they give
// their own: deformable and rigid services get the scene's objects of
// their kind (as `objects` and `bodies`), the tracker the camera and the
// marker, the AR view every object (kind kept) and the marker's id. A
// service with nothing to serve is marked unneeded.
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
    // An absent camera or marker is a null node, which converts to true: ask IsMap.
    if (scene.camera.IsMap())
      for (const auto& kv : scene.camera)
        if (!params[kv.first.Scalar()]) params[kv.first.Scalar()] = kv.second;
    if (scene.marker.IsMap()) {
      const std::pair<const char*, const char*> keys[] = {{"family", "family"}, {"size", "tag_size"}, {"id", "tag_id"}};
      for (const auto& [from, to] : keys)
        if (scene.marker[from] && !params[to]) params[to] = scene.marker[from];
    }
    if (!scene.camera.IsMap() && !own_params && scene.defined) s.unneeded = "the scene has no camera";
  } else if (s.kind == "ar_view") {
    if (!params["objects"]) params["objects"] = objects_of("");
    if (scene.marker.IsMap() && scene.marker["id"] && !params["tag_id"]) params["tag_id"] = scene.marker["id"];
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

void check_policy(const ServiceSpec& s, Mode mode) {
  if (mode == Mode::kLockstep && s.on_failure != OnFailure::kStopAll)
    throw ConfigError(s.where + ": on_failure: " + to_string(s.on_failure) +
                      " needs mode realtime (in lockstep the "
                      "clock waits on every follower at every step: one cannot be missing or rejoin)");
}

Mode parse_mode(const std::string& s) {
  if (s == "realtime") return Mode::kRealtime;
  if (s == "lockstep") return Mode::kLockstep;
  throw std::invalid_argument("mode must be 'realtime' or 'lockstep', not '" + s + "'");
}

std::vector<ForceSource> force_sources(const Deployment& d, const std::string& device) {
  std::vector<ForceSource> out;
  for (const ServiceSpec& s : d.services) {
    if (!s.unneeded.empty() || (s.kind != "rigid" && s.kind != "deformable")) continue;
    const YAML::Node dev = s.params["device"];
    if ((dev && dev.IsScalar() ? dev.Scalar() : std::string("omni")) != device) continue;
    const YAML::Node list = s.params[s.kind == "rigid" ? "bodies" : "objects"];
    if (!list || !list.IsSequence()) continue;
    for (const YAML::Node& o : list)
      if (o.IsMap() && o["name"] && o["name"].IsScalar()) out.push_back({o["name"].Scalar(), s.name, s.rate_hz});
  }
  return out;
}

Deployment load_deployment(const std::string& path) {
  const YAML::Node root = load_yaml(path);
  if (!root.IsMap()) throw ConfigError(path + ":1:1: a deployment must be a YAML map");
  check_keys(path, root, {"domain", "mode", "step", "duration", "security", "scene", "services"});

  Deployment d;
  d.file = path;
  d.services_where = path + ":1:1";
  if (auto n = root["domain"]) {
    const double v = config_number(path, n, "domain");
    if (v != std::floor(v) || v < 0 || v > kMaxDomain)
      throw config_error(path, n, "'domain' must be a whole number in 0.." + std::to_string(kMaxDomain));
    d.domain = static_cast<int>(v);
  }
  if (auto n = root["mode"]) {
    try {
      d.mode = parse_mode(config_text(path, n, "mode"));
    } catch (const std::invalid_argument& e) {
      throw config_error(path, n, e.what());
    }
  }
  if (auto n = root["step"]) {
    d.step_s = config_number(path, n, "step");
    if (d.step_s < 1e-6 || d.step_s > 1) throw config_error(path, n, "'step' must be in [1e-6, 1] s");
  }
  if (auto n = root["duration"]) {
    d.duration_s = config_number(path, n, "duration");
    if (d.duration_s < 0) throw config_error(path, n, "'duration' must not be negative");
  }
  if (auto n = root["security"]) {
    if (!n.IsMap()) throw config_error(path, n, "'security' must be a map with 'dir' (docs/security.md)");
    check_keys(path, n, {"dir"});
    if (!n["dir"]) throw config_error(path, n, "'security' must be a map with 'dir' (docs/security.md)");
    fs::path dir = config_text(path, n["dir"], "dir");
    if (dir.empty()) throw config_error(path, n["dir"], "'dir' must name a folder");
    if (dir.is_relative()) dir = fs::path(path).parent_path() / dir;
    d.security = dir.lexically_normal().string();
    d.security_where = adapters::config_where(path, n);
  }
  if (auto n = root["scene"]) d.scene = parse_scene(path, n);
  if (auto n = root["services"]) {
    if (!n.IsSequence()) throw config_error(path, n, "'services' must be a list");
    d.services_where = adapters::config_where(path, n);
    std::set<std::string> names;
    for (const auto& s : n) {
      ServiceSpec spec = parse_service(path, s);
      if (spec.name == "clock")
        throw config_error(path, s["name"], "the name 'clock' is reserved for the lockstep master");
      if (!names.insert(spec.name).second)
        throw config_error(path, s["name"], "service name '" + spec.name + "' is used twice");
      check_policy(spec, d.mode);
      add_scene(path, d.scene, spec, s);
      d.services.push_back(std::move(spec));
    }
  }
  return d;
}

Params::Params(std::string file, YAML::Node node) : file_(std::move(file)), node_(std::move(node)) {}

double Params::number(const std::string& key, double fallback, double lo, double hi) const {
  if (!node_ || !node_[key]) return fallback;
  const YAML::Node n = node_[key];
  const double v = config_number(file_, n, key);
  if (v < lo || v > hi)
    throw config_error(
        file_, n,
        "'" + key + "' = " + n.Scalar() + " is outside [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return v;
}

int Params::whole(const std::string& key, int fallback, int lo, int hi) const {
  const double v = number(key, fallback, lo, hi);
  if (v != std::floor(v))
    throw config_error(file_, node_[key], "'" + key + "' = " + node_[key].Scalar() + " must be a whole number");
  return int(v);
}

std::string Params::text(const std::string& key, const std::string& fallback,
                         const std::vector<std::string>& allowed) const {
  if (!node_ || !node_[key]) return fallback;
  const std::string v = config_text(file_, node_[key], key);
  if (std::find(allowed.begin(), allowed.end(), v) == allowed.end())
    throw config_error(file_, node_[key], "'" + key + "' must be one of " + join(allowed) + ", not '" + v + "'");
  return v;
}

bool Params::on(const std::string& key, bool fallback) const {
  if (!node_ || !node_[key]) return fallback;
  const std::string v = config_text(file_, node_[key], key);
  if (v == "on" || v == "true") return true;
  if (v == "off" || v == "false") return false;
  throw config_error(file_, node_[key], "'" + key + "' must be on or off (or true or false), not '" + v + "'");
}

std::string Params::string(const std::string& key, const std::string& fallback) const {
  if (!node_ || !node_[key]) return fallback;
  return config_text(file_, node_[key], key);
}

std::string Params::path(const std::string& key) const {
  if (!node_ || !node_[key]) return "";
  fs::path p = config_text(file_, node_[key], key);
  if (p.is_relative()) p = fs::path(file_).parent_path() / p;
  if (!fs::exists(p)) throw config_error(file_, node_[key], "'" + key + "': no file " + p.string());
  return p.string();
}

std::string Params::output_path(const std::string& key) const {
  if (!node_ || !node_[key]) return "";
  fs::path p = config_text(file_, node_[key], key);
  if (p.is_relative()) p = fs::path(file_).parent_path() / p;
  return p.string();
}

std::array<double, 3> Params::vec3(const std::string& key, const std::array<double, 3>& fallback) const {
  if (!node_ || !node_[key]) return fallback;
  const YAML::Node n = node_[key];
  if (!n.IsSequence() || n.size() != 3) throw config_error(file_, n, "'" + key + "' must be [x, y, z]");
  return {config_number(file_, n[0], key), config_number(file_, n[1], key), config_number(file_, n[2], key)};
}

std::vector<Params> Params::list(const std::string& key) const {
  std::vector<Params> out;
  if (!node_ || !node_[key]) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) throw config_error(file_, n, "'" + key + "' must be a list");
  for (const YAML::Node& item : n) {
    if (!item.IsMap()) throw config_error(file_, item, "each entry of '" + key + "' must be a map of keys");
    out.emplace_back(file_, item);
  }
  return out;
}

Params Params::map(const std::string& key) const {
  if (!node_ || !node_[key]) return Params(file_, YAML::Node(YAML::NodeType::Map));
  const YAML::Node n = node_[key];
  if (!n.IsMap()) throw config_error(file_, n, "'" + key + "' must be a map of keys");
  return Params(file_, n);
}

std::vector<double> Params::numbers(const std::string& key, double lo, double hi) const {
  std::vector<double> out;
  if (!node_ || !node_[key]) return out;
  const YAML::Node n = node_[key];
  if (!n.IsSequence()) throw config_error(file_, n, "'" + key + "' must be a list of numbers");
  for (const YAML::Node& item : n) {
    const double v = config_number(file_, item, key);
    if (v < lo || v > hi)
      throw config_error(file_, item,
                         "an entry of '" + key + "', " + item.Scalar() + ", is outside [" + std::to_string(lo) + ", " +
                             std::to_string(hi) + "]");
    out.push_back(v);
  }
  return out;
}

void Params::fail(const std::string& key, const std::string& what) const {
  throw config_error(file_, node_ && node_[key] ? node_[key] : node_, what);
}

void Params::allow_only(const std::vector<std::string>& allowed) const {
  if (node_ && node_.IsMap()) check_keys(file_, node_, allowed);
}

}  // namespace hcosim::services::runtime
