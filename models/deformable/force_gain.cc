#include "models/deformable/force_gain.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>

#include "models/deformable/compliance.h"
#include "models/deformable/hybrid_build.h"
#include "models/deformable/proxy.h"
#include "models/deformable/surface.h"
#include "models/fem/modal.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {

namespace {

// The behavior model of a spec stepped towards rest: implicit Euler at 1
// s steps, each close to a Newton step (CG to `tolerance`); the springs,
// or for the FEM and the modal model, the corotational FEM.
struct Settling {
  Settling(const HybridSpec& spec, double tolerance) {
    if (spec.behavior_model != BehaviorModel::springs) {
      models::fem::Options o;
      o.dt = 1, o.tolerance = tolerance;
      fem = std::make_unique<models::fem::Corotational>(hybrid_mesh(spec), spec.fem, o);
      state = models::fem::rest_state(fem->mesh());
    } else {
      models::massspring::Options o;
      o.integrator = models::massspring::Integrator::implicit_euler;
      o.dt = 1, o.tolerance = tolerance;
      springs = std::make_unique<models::massspring::Simulator>(hybrid_masses(spec), o);
      state = models::massspring::rest_state(springs->lattice());
    }
  }
  const Eigen::Matrix3Xd& rest() const { return fem ? fem->mesh().rest : springs->lattice().rest; }
  void step(const std::vector<models::massspring::PointForce>& loads) {
    fem ? void(fem->step(state, loads)) : void(springs->step(state, loads));
  }
  std::unique_ptr<models::massspring::Simulator> springs;
  std::unique_ptr<models::fem::Corotational> fem;
  models::massspring::State state;
};

// The behavior model of a spec with one mass held where it is put and the
// rest settled to rest around it. The modal model's is its kept modes'
// stiffness at the mass, in one step.
class Held {
 public:
  Held(const HybridSpec& spec, int mass, double tolerance) : mass_(mass), model_(spec, tolerance) {
    check_hybrid(mass >= 0 && mass < model_.state.x.cols(), "no mass " + std::to_string(mass));
    if (spec.behavior_model == BehaviorModel::modal) {
      stiffness_ = models::fem::Modal(*model_.fem, models::fem::ModalOptions{spec.behavior.dt, spec.modes})
                       .compliance(mass)
                       .inverse();
      modal_ = true;
    }
    model_.fem ? model_.fem->hold(mass, true) : model_.springs->hold(mass, true);
  }
  const Eigen::Matrix3Xd& rest() const { return model_.rest(); }
  // Puts the held mass at x and settles the rest until the holder's force
  // changes by under `change` of itself; returns that force (N).
  Eigen::Vector3d settle(const Eigen::Vector3d& x, double change) {
    if (modal_) return -stiffness_ * (x - rest().col(mass_));
    model_.state.x.col(mass_) = x;
    Eigen::Vector3d last = Eigen::Vector3d::Constant(1e300);
    for (int k = 0; k < 1000; ++k) {
      model_.step({});
      const Eigen::Vector3d f = force();
      if ((f - last).norm() <= change * f.norm()) break;
      last = f;
    }
    return force();
  }

 private:
  Eigen::Vector3d force() const {
    return model_.fem ? model_.fem->force_on(mass_, model_.state) : model_.springs->spring_force(mass_, model_.state);
  }
  int mass_;
  Settling model_;
  bool modal_ = false;
  Eigen::Matrix3d stiffness_;  // N/m, the modal model's at the mass
};

}  // namespace

Eigen::Vector3d behavior_static_force(const HybridSpec& spec, int mass, const Eigen::Vector3d& displacement) {
  check_hybrid(displacement.allFinite(), "the displacement must be finite");
  Held held(spec, mass, 1e-8);
  return held.settle(held.rest().col(mass) + displacement, 1e-9);
}

double power_law(const std::vector<double>& xs, const double* ys, double x) {
  if (x <= xs.front()) return ys[0] * x / xs.front();
  const std::size_t n = xs.size();
  const std::size_t k =
      std::min<std::size_t>(std::size_t(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin()), n - 1);
  if (!(ys[k - 1] > 0 && ys[k] > 0)) return 0;
  return ys[k - 1] * std::pow(ys[k] / ys[k - 1], std::log(x / xs[k - 1]) / std::log(xs[k] / xs[k - 1]));
}

double ForceGain::at(double d, bool stiff_side) const {
  return power_law(depth, (stiff_side && !stiff.empty() ? stiff : soft).data(), d);
}

namespace {

// N: a first guess at the force for `depth`, along the line through the
// last two (depth, force) found, or at the compliance at rest.
double extrapolated(const std::vector<double>& depths, const std::vector<double>& forces, double depth,
                    double compliance) {
  const std::size_t n = forces.size();
  if (n == 0) return depth / compliance;
  if (n == 1) return forces[0] * depth / depths[0];
  return forces[n - 1] + (depth - depths[n - 1]) * (forces[n - 1] - forces[n - 2]) / (depths[n - 1] - depths[n - 2]);
}

// The behavior model of a spec loaded at one point of its drawn surface
// as touch() loads it: a force along -n spread over masses by a map row,
// settled (Settling) from where the last load left it. (The modal model
// is linear: its answer is its compliance's.)
class Pressed {
 public:
  Pressed(const HybridSpec& spec, std::vector<std::pair<int, double>> row, const Eigen::Vector3d& n, double tolerance)
      : row_(std::move(row)), n_(n), model_(spec, tolerance) {}
  // m: how far the point sinks along -n under `force` (N), settled until
  // that changes by under `change` of itself a step.
  double sink(double force, double change) {
    std::vector<models::massspring::PointForce> loads;
    for (const auto& [m, w] : row_) loads.push_back({m, -force * w * n_});
    double last = 1e300;
    for (int k = 0; k < 1000; ++k) {
      model_.step(loads);
      const double s = at();
      if (std::abs(s - last) <= change * std::abs(s)) break;
      last = s;
    }
    return at();
  }
  // N: the force under which the point sinks `depth`, from `guess`: by
  // secants, within the forces found to sink it less and more once there
  // are both (regula falsi; bisection where the secant leaves them), as
  // the force's growth with depth slows where cells give way.
  double force_for(double depth, double guess) {
    const double tolerance = 1e-2 * depth;
    double f0 = guess, s0 = sink(f0, 3e-4);
    if (std::abs(s0 - depth) <= tolerance) return f0;
    double f1 = s0 > 0 ? f0 * depth / s0 : 2 * f0, s1 = sink(f1, 3e-4);
    double lo = 0, hi = 1e300;  // N: forces that sink it less and more than depth
    auto bracket = [&](double f, double sunk) { sunk < depth ? lo = std::max(lo, f) : hi = std::min(hi, f); };
    bracket(f0, s0), bracket(f1, s1);
    for (int k = 0; k < 40 && std::abs(s1 - depth) > tolerance; ++k) {
      double f = s1 != s0 ? f1 + (depth - s1) * (f1 - f0) / (s1 - s0) : 2 * f1;
      if (!(f > lo && f < hi)) f = hi < 1e300 ? 0.5 * (lo + hi) : 2 * std::max(f1, lo);
      f0 = f1, s0 = s1, f1 = f, s1 = sink(f1, 3e-4);
      bracket(f1, s1);
    }
    return f1;
  }

 private:
  double at() const {
    double s = 0;
    for (const auto& [m, w] : row_) s -= w * n_.dot(model_.state.x.col(m) - model_.rest().col(m));
    return s;
  }
  std::vector<std::pair<int, double>> row_;
  Eigen::Vector3d n_;
  Settling model_;
};

// The point of the drawn surface nearest `point` (rest, world), loaded as
// touch() loads a proxy there: along its inward normal (or `along`, where
// not zero), spread over its face's vertices by their barycentric weights
// and from each over the masses by its map row. `compliance` is what
// Hybrid::force_scale takes for it: its vertices' compliances along that
// direction, weighted alike.
struct SurfaceLoad {
  std::vector<std::pair<int, double>> row;  // mass, weight
  Eigen::Vector3d normal;
  double compliance = 0;  // m/N
};

SurfaceLoad surface_load(const HybridSpec& spec, const models::massspring::Voxels& voxels,
                         const models::massspring::Lattice& lat, const models::fem::Modal* modal,
                         const models::massspring::TriangleMesh& visual, const Cage& cage, const Eigen::Vector3d& point,
                         const Eigen::Vector3d& along = Eigen::Vector3d::Zero()) {
  const MeshProxy mesh(visual.triangles, int(visual.vertices.cols()));
  const SurfacePoint p = mesh.closest(visual.vertices, point);
  const Eigen::Vector3i& face = mesh.triangle(p.face);
  Eigen::Matrix3Xd at(3, 3), normals(3, 3);
  const Eigen::Matrix3Xd all = vertex_normals(visual.vertices, visual.triangles);
  for (int k = 0; k < 3; ++k) {
    at.col(k) = visual.vertices.col(face[k]);
    normals.col(k) = along.isZero() ? Eigen::Vector3d(all.col(face[k])) : Eigen::Vector3d(-along.normalized());
  }
  const Weights rows = map_rows(spec, voxels, cage, at);
  const std::vector<double> c = surface_compliance(spec, lat, modal, rows, cage.masses, normals);
  SurfaceLoad l;
  std::map<int, double> by_mass;
  for (int k = 0; k < 3; ++k) {
    for (Weights::InnerIterator w(rows, k); w; ++w) by_mass[cage.masses[w.col()]] += p.bary[k] * w.value();
    l.compliance += p.bary[k] * c[k];
  }
  l.row.assign(by_mass.begin(), by_mass.end());
  l.normal = along.isZero() ? mesh.normal(visual.vertices, p) : Eigen::Vector3d(-along.normalized());
  return l;
}

// N, by depth (increasing): the forces under which a surface load's
// point sinks that deep, pressed deeper step by step as a stylus presses
// (past a snap-through a force has two depths, and the press follows the
// one it is on); the modal model's, its compliance's.
std::vector<double> surface_forces(const HybridSpec& spec, const models::fem::Modal* modal, const SurfaceLoad& l,
                                   const std::vector<double>& depths) {
  std::vector<double> f;
  if (modal) {
    for (const double d : depths) f.push_back(d / l.compliance);
    return f;
  }
  // A loose CG tolerance: each settle step is then a rougher Newton step,
  // but settling goes on until the sink stops changing, so where it ends
  // is the same (the forces agree to 4 digits with 1e-5) in under half
  // the time.
  Pressed pressed(spec, l.row, l.normal, 1e-3);
  std::vector<double> at, force;  // m and N: every depth pressed to, and its force
  for (const double d : depths) {
    const double last = at.empty() ? 0 : at.back();
    const int steps = std::max(1, int(std::ceil((d - last) / (0.05 * depths.back()))));
    for (int k = 1; k <= steps; ++k) {
      const double x = last + (d - last) * k / steps;
      force.push_back(pressed.force_for(x, extrapolated(at, force, x, l.compliance)));
      at.push_back(x);
    }
    f.push_back(force.back());
  }
  return f;
}

}  // namespace

std::vector<double> behavior_surface_force(const HybridSpec& spec, const Eigen::Vector3d& point,
                                           const std::vector<double>& depths, const Eigen::Vector3d& along) {
  check_hybrid(point.allFinite(), "the point must be finite");
  check_hybrid(along.allFinite(), "the direction must be finite");
  for (std::size_t j = 0; j < depths.size(); ++j)
    check_hybrid(std::isfinite(depths[j]) && depths[j] > (j > 0 ? depths[j - 1] : 0),
                 "the depths must be finite, > 0 and increasing");
  const models::massspring::Voxels voxels = hybrid_voxels(spec);
  const models::massspring::Lattice lat = hybrid_masses(spec);
  const models::massspring::TriangleMesh visual = hybrid_visual(spec);
  const Cage cage = map_cage(spec, voxels, lat, visual);
  const std::unique_ptr<models::fem::Modal> modal = modal_of(spec);
  return surface_forces(spec, modal.get(), surface_load(spec, voxels, lat, modal.get(), visual, cage, point, along),
                        depths);
}

ForceGain force_gain(const HybridSpec& spec, const Weights& map) {
  const models::massspring::Voxels voxels = hybrid_voxels(spec);
  const models::massspring::Lattice lat = hybrid_masses(spec);
  const models::massspring::TriangleMesh visual = hybrid_visual(spec);
  const Cage cage = map_cage(spec, voxels, lat, visual);
  const double extent = rest_box(spec).sizes().minCoeff();
  ForceGain gain;
  // Closer where the S-Chain's growth is steepest: a stiff side's short
  // ranges move a new ring of chains every few tenths of a millimetre.
  for (const double f : {0.02, 0.03, 0.04, 0.06, 0.08, 0.1,  0.12, 0.14, 0.16, 0.2, 0.24,
                         0.28, 0.32, 0.4,  0.48, 0.56, 0.64, 0.72, 0.8,  0.88, 1.0})
    gain.depth.push_back(0.25 * extent * f);
  // Each side's gain element's point of the drawn surface, pressed in turn
  // to every depth, and its chains pressed as deep.
  const std::unique_ptr<models::fem::Modal> modal = modal_of(spec);
  const SChain chain(hybrid_chains(spec), spec.relax_rate, spec.limit_stiffness);
  auto side = [&](bool stiff, double* compliance) {
    const SurfaceLoad l =
        surface_load(spec, voxels, lat, modal.get(), visual, cage, find_gain_point(spec, voxels, chain, stiff).first);
    *compliance = l.compliance;
    return surface_forces(spec, modal.get(), l, gain.depth);
  };
  gain.soft = side(false, &gain.soft_compliance);
  if (spec.stiff_ratio != 1) gain.stiff = side(true, &gain.stiff_compliance);
  check_hybrid(
      map.size() == 0 || (map.rows() == visual.vertices.cols() && map.cols() == Eigen::Index(cage.masses.size())),
      "the visual map given must have a row per visual vertex and a column per cage mass");
  if (lat.size() <= ForceGain::kMostMasses)
    gain.compliance =
        surface_compliance(spec, lat, modal.get(), map.size() ? map : map_rows(spec, voxels, cage, visual.vertices),
                           cage.masses, vertex_normals(visual.vertices, visual.triangles));
  return gain;
}

ForceGain shared_force_gain(const HybridSpec& s, const Weights& map) {
  std::ostringstream o;
  o << std::hexfloat;
  for (const double v : gain_key(s)) o << v << ' ';
  static std::mutex m;
  static std::map<std::string, ForceGain> seen;
  {
    const std::lock_guard<std::mutex> l(m);
    if (const auto it = seen.find(o.str()); it != seen.end()) return it->second;
  }
  ForceGain g = force_gain(s, map);
  const std::lock_guard<std::mutex> l(m);
  return seen.emplace(o.str(), std::move(g)).first->second;
}

}  // namespace hcosim::models::deformable
