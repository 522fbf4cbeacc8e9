#include "models/rigid/mujoco_world.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

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

// solref (-stiffness, -damping) for restitution e, lasting `steps` steps
// per half-period at dt.
std::string solref(double e, double dt, const MujocoContact& c) {
  const double k = std::pow(M_PI / (c.contact_steps * dt), 2);
  const double le = std::log(std::max(e, 1e-6));
  const double z = e >= 1 ? 0 : -le / std::sqrt(M_PI * M_PI + le * le);
  std::ostringstream o;
  o.precision(17);
  o << -k << " " << -2 * z * std::sqrt(k);
  return o.str();
}

std::string pair(const std::string& a, const std::string& b, const Material& m, double dt, const MujocoContact& c) {
  std::ostringstream o;
  o.precision(17);
  o << "<pair geom1=\"" << a << "\" geom2=\"" << b << "\" condim=\"" << (m.friction > 0 ? 3 : 1) << "\" friction=\""
    << m.friction << " " << m.friction << " 0 0 0\" solref=\"" << solref(m.restitution, dt, c) << "\" solimp=\""
    << c.impedance << " " << c.impedance << " 0.001 0.5 2\"/>\n";
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
      << (spec.pair.friction > 0 ? 3 : 1) << "\" friction=\"" << spec.pair.friction << " 0 0\" solref=\""
      << solref(spec.pair.restitution, dt, c) << "\" solimp=\"" << c.impedance << " " << c.impedance
      << " 0.001 0.5 2\"/></body>\n";
  }
  o << "<body name=\"tip\"><joint type=\"slide\" axis=\"1 0 0\"/><joint type=\"slide\" axis=\"0 1 0\"/>"
    << "<joint type=\"slide\" axis=\"0 0 1\"/><geom name=\"tip\" type=\"sphere\" size=\""
    << std::max(spec.tip_radius, kMinTipRadius) << "\" mass=\"" << spec.tip_mass
    << "\"/></body>\n</worldbody>\n<contact>\n";
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    const std::string g = "g" + std::to_string(i);
    o << pair("tip", g, spec.tip, dt, c);
    if (spec.ground) o << pair("floor", g, spec.floor, dt, c);
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
