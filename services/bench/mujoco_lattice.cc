#include "services/bench/mujoco_lattice.h"

#include <sstream>
#include <stdexcept>

#include <mujoco/mujoco.h>

#include "models/mjcf/load.h"

namespace hcosim::services::bench {

using models::massspring::Lattice;
using models::massspring::PointForce;
using models::massspring::Spring;

struct MujocoLattice::Impl {
  mjModel* model = nullptr;
  mjData* data = nullptr;
  Eigen::Matrix3Xd rest;
  std::vector<int> body;  // mass -> MuJoCo body id
  std::vector<int> qadr;  // mass -> first qpos address, -1 if anchored
};

namespace {

int free_masses(const Lattice& l) {
  int n = 0;
  for (auto a : l.anchored) n += !a;
  return n;
}

}  // namespace

double MujocoLattice::data_bytes(const Lattice& l) {
  const double nv = 3.0 * free_masses(l), nt = double(l.springs.size());
  // ten_J (mjtNum) and ten_J_colind (int), each tendons x dofs.
  return nt * nv * (sizeof(mjtNum) + sizeof(int));
}

std::string MujocoLattice::xml(const Lattice& l, double dt, const std::string& integrator) {
  const int nv = 3 * free_masses(l);
  std::ostringstream o;
  o.precision(17);
  // The solver's scratch stack grows with the dofs and tendons.
  o << "<mujoco model=\"lattice\">\n<size nstack=\"" << 1'000'000 + 64L * (nv + long(l.springs.size())) << "\"/>\n"
    << "<option timestep=\"" << dt << "\" integrator=\"" << integrator << "\" gravity=\"" << l.gravity.x() << " "
    << l.gravity.y() << " " << l.gravity.z() << "\">\n<flag contact=\"disable\"/>\n</option>\n<worldbody>\n";
  for (int i = 0; i < l.size(); ++i) {
    const Eigen::Vector3d p = l.rest.col(i);
    o << "<body name=\"m" << i << "\" pos=\"" << p.x() << " " << p.y() << " " << p.z() << "\">";
    if (!l.anchored[i]) {
      o << "<inertial pos=\"0 0 0\" mass=\"" << l.mass[i] << "\" diaginertia=\"1e-9 1e-9 1e-9\"/>";
      for (const char* axis : {"1 0 0", "0 1 0", "0 0 1"})
        o << "<joint type=\"slide\" axis=\"" << axis << "\" damping=\"" << l.drag << "\"/>";
    }
    o << "<site name=\"s" << i << "\"/></body>\n";
  }
  o << "</worldbody>\n<tendon>\n";
  for (const Spring& s : l.springs)
    o << "<spatial stiffness=\"" << s.k << "\" damping=\"" << s.b << "\" springlength=\"" << s.rest
      << "\"><site site=\"s" << s.i << "\"/><site site=\"s" << s.j << "\"/></spatial>\n";
  o << "</tendon>\n</mujoco>\n";
  return o.str();
}

MujocoLattice::MujocoLattice(const Lattice& l, double dt, const std::string& integrator)
    : impl_(std::make_unique<Impl>()) {
  models::massspring::check(l);
  if (integrator != "Euler" && integrator != "RK4")
    throw std::invalid_argument("mujoco lattice: integrator must be Euler or RK4, got '" + integrator + "'");
  const std::string text = xml(l, dt, integrator);
  models::mjcf::load("mujoco lattice", text, impl_->model, impl_->data);
  impl_->rest = l.rest;
  impl_->body.resize(l.size());
  impl_->qadr.assign(l.size(), -1);
  for (int i = 0; i < l.size(); ++i) {
    const int b = mj_name2id(impl_->model, mjOBJ_BODY, ("m" + std::to_string(i)).c_str());
    impl_->body[i] = b;
    if (impl_->model->body_jntnum[b] == 3) impl_->qadr[i] = impl_->model->jnt_qposadr[impl_->model->body_jntadr[b]];
  }
}

MujocoLattice::~MujocoLattice() {
  if (impl_->data) mj_deleteData(impl_->data);
  if (impl_->model) mj_deleteModel(impl_->model);
}

void MujocoLattice::step(const std::vector<PointForce>& loads) {
  mjData* d = impl_->data;
  mju_zero(d->xfrc_applied, 6 * impl_->model->nbody);
  for (const PointForce& p : loads)
    for (int c = 0; c < 3; ++c) d->xfrc_applied[6 * impl_->body[p.mass] + c] += p.force[c];
  mj_step(impl_->model, d);
  for (int w = 0; w < mjNWARNING; ++w)
    if (d->warning[w].number > 0)
      throw std::runtime_error(std::string("mujoco lattice: MuJoCo warning '") +
                               mju_warningText(w, d->warning[w].lastinfo) + "' at t = " + std::to_string(d->time) +
                               " s");
}

Eigen::Matrix3Xd MujocoLattice::positions() const {
  Eigen::Matrix3Xd x = impl_->rest;
  for (std::size_t i = 0; i < impl_->qadr.size(); ++i)
    if (impl_->qadr[i] >= 0)
      for (int c = 0; c < 3; ++c) x(c, i) += impl_->data->qpos[impl_->qadr[i] + c];
  return x;
}

double MujocoLattice::time() const { return impl_->data->time; }

}  // namespace hcosim::services::bench
