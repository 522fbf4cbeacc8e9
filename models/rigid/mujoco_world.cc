#include "models/rigid/mujoco_world.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <utility>

#include <mujoco/mujoco.h>

#include "models/mjcf/load.h"

namespace hcosim::models::rigid {

struct MujocoWorld::Impl {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  WorldSpec spec;
  std::vector<Body> constants;                    // shape, size, mass of each body
  std::vector<int> body;                          // MuJoCo body id of each
  std::vector<Eigen::Matrix<double, 6, 1>> load;  // force, torque on each (world)
  int tip_body = -1, tip_q = -1;
};

namespace {

constexpr double kMinTipRadius = 1e-4;  // MuJoCo's sphere needs a positive radius

// A body's geom as the world has it, named `name`, with the joint(s)
// given.
std::string body_xml(const Body& b, const std::string& name, const Eigen::Vector3d& at, const std::string& joints) {
  std::ostringstream o;
  o.precision(17);
  o << "<body name=\"" << name << "\" pos=\"" << at.x() << " " << at.y() << " " << at.z() << "\">" << joints
    << "<geom name=\"" << name << "\" type=\"" << (b.shape == Shape::cube ? "box" : "sphere") << "\" size=\"";
  if (b.shape == Shape::cube) o << b.size << " " << b.size << " ";
  o << b.size << "\" mass=\"" << b.mass << "\"/></body>";
  return o.str();
}

constexpr const char* kFree = "<freejoint/>";
constexpr const char* kSlides =
    "<joint type=\"slide\" axis=\"1 0 0\"/><joint type=\"slide\" axis=\"0 1 0\"/>"
    "<joint type=\"slide\" axis=\"0 0 1\"/>";

// The damping b (1/s) of a contact of stiffness k (solref -k -b) that
// makes MuJoCo's own head-on hit of two bodies rebound at restitution e.
// A linear spring-damper of damping ratio z rebounds at
// exp(-z pi / sqrt(1 - z^2)), but MuJoCo's contact cannot pull, so it lets
// go before that damper is done, and the share of the reference
// acceleration it reaches depends on the bodies' inertias, so the same
// solref rebounds differently for different pairs (with that formula the
// `inelastic` cross-check was 7 % off the analytic impulse). `world` holds
// two bodies touching along x, a contact pair "a"-"b" between them; the
// dof `moving` is sent at 1 m/s into dof `still` (-1: a fixed geom), or
// -1 m/s if `back`, from a fraction of a step away. The damping is found
// by bisection, once per model.
double damping_for(double e, double k, double dt, const MujocoContact& c, const std::string& world, int moving,
                   int still, bool back) {
  std::ostringstream o;
  o.precision(17);
  o << "<mujoco model=\"rebound\"><option timestep=\"" << dt << "\" integrator=\"Euler\" gravity=\"0 0 0\"/>"
    << "<default><geom contype=\"0\" conaffinity=\"0\"/></default><worldbody>" << world
    << "</worldbody><contact><pair geom1=\"a\" geom2=\"b\" condim=\"1\" solref=\"" << -k << " 0\" solimp=\""
    << c.impedance << " " << c.impedance << " 0.001 0.5 2\"/></contact></mujoco>";
  static std::mutex mutex;
  static std::map<std::pair<std::string, double>, double> known;
  std::lock_guard<std::mutex> lock(mutex);
  const auto key = std::make_pair(o.str(), e);
  if (const auto it = known.find(key); it != known.end()) return it->second;
  mjModel* m = nullptr;
  mjData* d = nullptr;
  models::mjcf::load("mujoco world: restitution", o.str(), m, d);
  const double sign = back ? -1 : 1;
  const int joint = m->dof_jntid[moving];
  const int q = m->jnt_qposadr[joint] + moving - m->jnt_dofadr[joint];
  auto relative = [&] { return sign * (d->qvel[moving] - (still >= 0 ? d->qvel[still] : 0)); };
  // The rebound of a contact that begins `phase` of a step after a step
  // boundary: MuJoCo's first step in contact sees up to a step's worth of
  // penetration, which moves the rebound by several hundredths at 12
  // steps a half-period, so the mean over 8 phases is what is tuned.
  auto rebound = [&](double b) {
    m->pair_solref[1] = -b;
    double sum = 0;
    for (int j = 0; j < 8; ++j) {
      mj_resetData(m, d);
      d->qpos[q] -= sign * (j + 0.5) / 8 * dt;
      d->qvel[moving] = sign;
      // Until 50 steps past the last contact.
      for (int n = 0, last = 0; n < last + 50 && n < 100000; ++n) {
        mj_step(m, d);
        if (d->ncon > 0) last = n;
      }
      sum -= relative();
    }
    return sum / 8;
  };
  // Past b dt = 1 MuJoCo's damping no longer settles within a step and
  // the rebound grows again: the bracket stays below it.
  double lo = 0, hi = std::min(8 * std::sqrt(k), 1 / dt);
  for (int i = 0; i < 50 && hi - lo > 1e-9 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (rebound(mid) > e ? lo : hi) = mid;
  }
  mj_deleteData(d);
  mj_deleteModel(m);
  return known[key] = 0.5 * (lo + hi);
}

// The contact's stiffness (1/s^2): a half-period of `steps` steps at dt.
double stiffness(double dt, const MujocoContact& c) { return std::pow(M_PI / (c.contact_steps * dt), 2); }

// solref (-stiffness, -damping) for restitution e between the bodies of
// `world` (damping_for); e = 1: no damping.
std::string solref(double e, double dt, const MujocoContact& c, const std::string& world, int moving, int still,
                   bool back = false) {
  const double k = stiffness(dt, c);
  std::ostringstream o;
  o.precision(17);
  o << -k << " " << -(e < 1 ? damping_for(e, k, dt, c, world, moving, still, back) : 0.0);
  return o.str();
}

std::string solimp(const MujocoContact& c) {
  std::ostringstream o;
  o.precision(17);
  o << c.impedance << " " << c.impedance << " 0.001 0.5 2";
  return o.str();
}

// How far a body reaches from its centre along x (and z): its radius, or
// its half-size.
double extent(const Body& b) { return b.size; }

std::string pair(const std::string& a, const std::string& b, const Material& m, const std::string& ref,
                 const MujocoContact& c) {
  std::ostringstream o;
  o.precision(17);
  o << "<pair geom1=\"" << a << "\" geom2=\"" << b << "\" condim=\"" << (m.friction > 0 ? 3 : 1) << "\" friction=\""
    << m.friction << " " << m.friction << " 0 0 0\" solref=\"" << ref << "\" solimp=\"" << solimp(c) << "\"/>\n";
  return o.str();
}

}  // namespace

std::string MujocoWorld::xml(const WorldSpec& spec, const std::vector<Body>& bodies, double dt,
                             const MujocoContact& c) {
  std::ostringstream o;
  o.precision(17);
  // A cube has up to 4 contacts with the plane (8 with its corners in
  // it), a few with each body it touches (8 allowed for), and each
  // frictional contact 3 constraint rows.
  const std::size_t ncon = 16 * bodies.size() + 8;
  o << "<mujoco model=\"rigid\">\n<size nconmax=\"" << ncon << "\" njmax=\"" << 3 * ncon << "\"/>\n<option timestep=\""
    << dt << "\" integrator=\"Euler\" cone=\"elliptic\" gravity=\"" << spec.gravity.x() << " " << spec.gravity.y()
    << " " << spec.gravity.z() << "\"/>\n"
    << "<default><geom contype=\"0\" conaffinity=\"0\"/></default>\n<worldbody>\n";
  if (spec.ground) o << "<geom name=\"floor\" type=\"plane\" size=\"0 0 1\"/>\n";
  // Body against body: one solref on every body geom (MuJoCo's own
  // filter pairs them), tuned on two of the first body.
  std::string pair_ref;
  if (!bodies.empty()) {
    const Body& b = bodies[0];
    pair_ref = solref(spec.pair.restitution, dt, c,
                      body_xml(b, "a", Eigen::Vector3d::Zero(), kFree) +
                          body_xml(b, "b", Eigen::Vector3d(-2 * extent(b), 0, 0), kFree),
                      6, 0);
  }
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const Body& b = bodies[i];
    o << "<body name=\"b" << i << "\" pos=\"" << b.x.x() << " " << b.x.y() << " " << b.x.z() << "\" quat=\"" << b.q.w()
      << " " << b.q.x() << " " << b.q.y() << " " << b.q.z() << "\"><freejoint/><geom name=\"g" << i << "\" type=\""
      << (b.shape == Shape::cube ? "box" : "sphere") << "\" size=\"";
    if (b.shape == Shape::cube) o << b.size << " " << b.size << " ";
    // Body-body contacts come from MuJoCo's own collision filter (every
    // body geom has contype and conaffinity 2, the tip and the floor 0),
    // with the pair material on every body geom, so that n bodies need no
    // n^2 explicit pairs.
    o << b.size << "\" mass=\"" << b.mass << "\" contype=\"2\" conaffinity=\"2\" condim=\""
      << (spec.pair.friction > 0 ? 3 : 1) << "\" friction=\"" << spec.pair.friction << " 0 0\" solref=\"" << pair_ref
      << "\" solimp=\"" << solimp(c) << "\"/></body>\n";
  }
  const double tip_r = std::max(spec.tip_radius, kMinTipRadius);
  Body tip;
  tip.shape = Shape::sphere, tip.size = tip_r, tip.mass = spec.tip_mass;
  o << body_xml(tip, "tip", Eigen::Vector3d::Zero(), kSlides) << "\n</worldbody>\n<contact>\n";
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string g = "g" + std::to_string(i);
    const Body& b = bodies[i];
    // The tip's own head-on hit on this body (on a face's centre), and the
    // body dropped flat on the plane.
    const std::string tip_world = body_xml(b, "a", Eigen::Vector3d::Zero(), kFree) +
                                  body_xml(tip, "b", Eigen::Vector3d(-extent(b) - tip_r, 0, 0), kSlides);
    o << pair("tip", g, spec.tip, solref(spec.tip.restitution, dt, c, tip_world, 6, 0), c);
    if (spec.ground) {
      const std::string floor_world = "<geom name=\"a\" type=\"plane\" size=\"0 0 1\"/>" +
                                      body_xml(b, "b", Eigen::Vector3d(0, 0, extent(b)), kFree);
      o << pair("floor", g, spec.floor, solref(spec.floor.restitution, dt, c, floor_world, 2, -1, true), c);
    }
  }
  o << "</contact>\n</mujoco>\n";
  return o.str();
}

MujocoWorld::MujocoWorld(const WorldSpec& spec, const std::vector<Body>& bodies, double dt, const MujocoContact& c)
    : impl_(std::make_unique<Impl>()) {
  check(spec);
  check(bodies);
  if (!(dt > 0)) throw std::invalid_argument("mujoco world: dt must be > 0");
  if (!(c.contact_steps >= 2) || !(c.impedance > 0 && c.impedance < 1))
    throw std::invalid_argument("mujoco world: contact_steps must be >= 2 and impedance in (0, 1)");
  const std::string text = xml(spec, bodies, dt, c);
  models::mjcf::load("mujoco world", text, impl_->model, impl_->data);
  impl_->spec = spec;
  impl_->constants = bodies;
  mjModel* m = impl_->model;
  mjData* d = impl_->data;
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const int id = mj_name2id(m, mjOBJ_BODY, ("b" + std::to_string(i)).c_str());
    impl_->body.push_back(id);
    const int qv = m->jnt_dofadr[m->body_jntadr[id]];
    const Body& b = bodies[i];
    // Free joint: linear velocity in world, angular velocity in the body frame.
    for (int k = 0; k < 3; ++k) d->qvel[qv + k] = b.v[k];
    const Eigen::Vector3d wl = b.q.conjugate() * b.w;
    for (int k = 0; k < 3; ++k) d->qvel[qv + 3 + k] = wl[k];
  }
  impl_->load.assign(bodies.size(), Eigen::Matrix<double, 6, 1>::Zero());
  impl_->tip_body = mj_name2id(m, mjOBJ_BODY, "tip");
  impl_->tip_q = m->jnt_qposadr[m->body_jntadr[impl_->tip_body]];
  mj_forward(m, d);
}

MujocoWorld::~MujocoWorld() {
  if (impl_->data) mj_deleteData(impl_->data);
  if (impl_->model) mj_deleteModel(impl_->model);
}

void MujocoWorld::set_load(std::size_t i, const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  if (i >= impl_->body.size()) throw std::invalid_argument("mujoco world: no body " + std::to_string(i) + " to load");
  if (!force.allFinite() || !torque.allFinite()) throw std::invalid_argument("mujoco world: load is not finite");
  impl_->load[i] << force, torque;
}

void MujocoWorld::set_tip(const Tip& t) {
  if (!t.x.allFinite() || !t.v.allFinite()) throw std::invalid_argument("mujoco world: tip state is not finite");
  const int q = impl_->tip_q, dof = impl_->model->jnt_dofadr[impl_->model->body_jntadr[impl_->tip_body]];
  for (int k = 0; k < 3; ++k) impl_->data->qpos[q + k] = t.x[k], impl_->data->qvel[dof + k] = t.v[k];
}

Tip MujocoWorld::tip() const {
  Tip t;
  const int q = impl_->tip_q, dof = impl_->model->jnt_dofadr[impl_->model->body_jntadr[impl_->tip_body]];
  for (int k = 0; k < 3; ++k) t.x[k] = impl_->data->qpos[q + k], t.v[k] = impl_->data->qvel[dof + k];
  return t;
}

Body MujocoWorld::body(std::size_t i) const {
  const mjModel* m = impl_->model;
  const mjData* d = impl_->data;
  const int j = m->body_jntadr[impl_->body[i]], q = m->jnt_qposadr[j], v = m->jnt_dofadr[j];
  Body b = impl_->constants[i];
  b.x = Eigen::Vector3d(d->qpos[q], d->qpos[q + 1], d->qpos[q + 2]);
  b.q = Eigen::Quaterniond(d->qpos[q + 3], d->qpos[q + 4], d->qpos[q + 5], d->qpos[q + 6]).normalized();
  b.v = Eigen::Vector3d(d->qvel[v], d->qvel[v + 1], d->qvel[v + 2]);
  b.w = b.q * Eigen::Vector3d(d->qvel[v + 3], d->qvel[v + 4], d->qvel[v + 5]);
  b.sleeping = false;
  return b;
}

std::vector<Body> MujocoWorld::bodies() const {
  std::vector<Body> out;
  for (std::size_t i = 0; i < impl_->constants.size(); ++i) out.push_back(body(i));
  return out;
}

void MujocoWorld::step() {
  const mjModel* m = impl_->model;
  mjData* d = impl_->data;
  const Drag& drag = impl_->spec.drag;
  mju_zero(d->xfrc_applied, 6 * m->nbody);
  for (std::size_t i = 0; i < impl_->constants.size(); ++i) {
    const Body b = body(i);
    const Eigen::Vector3d f = impl_->load[i].head<3>() - (drag.linear + drag.quadratic * b.v.norm()) * b.v;
    const Eigen::Vector3d t =
        impl_->load[i].tail<3>() - (drag.angular_linear + drag.angular_quadratic * b.w.norm()) * b.w;
    for (int k = 0; k < 3; ++k)
      d->xfrc_applied[6 * impl_->body[i] + k] = f[k], d->xfrc_applied[6 * impl_->body[i] + 3 + k] = t[k];
  }
  for (int k = 0; k < 3; ++k) d->xfrc_applied[6 * impl_->tip_body + k] = -impl_->spec.tip_mass * impl_->spec.gravity[k];
  mj_step(m, d);
  for (int w = 0; w < mjNWARNING; ++w)
    if (d->warning[w].number > 0)
      throw std::runtime_error(std::string("mujoco world: MuJoCo warning '") +
                               mju_warningText(w, d->warning[w].lastinfo) + "' at t = " + std::to_string(d->time) +
                               " s");
}

Eigen::Vector3d MujocoWorld::momentum() const {
  Eigen::Vector3d p = impl_->spec.tip_mass * tip().v;
  for (const Body& b : bodies()) p += models::rigid::momentum(b);
  return p;
}

Eigen::Vector3d MujocoWorld::angular_momentum() const {
  const Tip t = tip();
  Eigen::Vector3d l = impl_->spec.tip_mass * t.x.cross(t.v);
  for (const Body& b : bodies()) l += models::rigid::angular_momentum(b);
  return l;
}

Eigen::Vector3d MujocoWorld::subtree_angular_momentum() const {
  mj_forward(impl_->model, impl_->data);  // after mj_step, positions are a step ahead of xpos
  mj_subtreeVel(impl_->model, impl_->data);
  return Eigen::Vector3d(impl_->data->subtree_angmom[0], impl_->data->subtree_angmom[1],
                         impl_->data->subtree_angmom[2]);
}

double MujocoWorld::kinetic_energy() const {
  double e = 0.5 * impl_->spec.tip_mass * tip().v.squaredNorm();
  for (const Body& b : bodies()) e += models::rigid::kinetic_energy(b);
  return e;
}

}  // namespace hcosim::models::rigid
