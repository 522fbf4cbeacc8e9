#include "models/deformable/elastic_surface.h"

#include <cmath>
#include <stdexcept>

namespace hcosim::models::deformable {

namespace {

void need(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("elastic surface: " + what);
}

}  // namespace

const char* name(Shape s) { return s == Shape::sheet ? "sheet" : "semisphere"; }

ElasticSurface::ElasticSurface(const SurfaceSpec& spec) : spec_(spec), cone_(spec.friction) {
  need(spec.resolution >= 3 && spec.resolution <= 400, "resolution must be in [3, 400]");
  need(spec.size > 0 && std::isfinite(spec.size), "size must be finite and > 0");
  need(spec.centre.allFinite(), "centre must be finite");
  need(spec.prestretch >= 0 && spec.prestretch < 0.5, "prestretch must be in [0, 0.5)");
  need(spec.bending >= 0 && spec.bending <= 100, "bending must be in [0, 100]");
  need(spec.contact_stiffness > 0 && std::isfinite(spec.contact_stiffness), "contact_stiffness must be finite and > 0");
  const int n = spec.resolution;
  models::massspring::Lattice l;
  if (spec.shape == Shape::sheet) {
    l = models::massspring::make_sheet(n, n, spec.size / (n - 1), spec.material);
    l.rest.colwise() += spec.centre - Eigen::Vector3d(0.5 * spec.size, 0.5 * spec.size, 0);
    for (models::massspring::Spring& sp : l.springs) sp.rest *= 1 - spec.prestretch;
    for (int j = 0; j + 1 < n; ++j)
      for (int i = 0; i + 1 < n; ++i) {
        const int a = i + n * j;
        triangles_.emplace_back(a, a + 1, a + n + 1);
        triangles_.emplace_back(a, a + n + 1, a + n);
      }
  } else {
    const int segments = 4 * n;
    l = models::massspring::make_semisphere(n, segments, spec.size, spec.material);
    l.rest.colwise() += spec.centre;
    const int pole = n * segments;
    auto id = [segments](int r, int s) { return r * segments + s % segments; };
    for (int r = 0; r < n; ++r)
      for (int s = 0; s < segments; ++s) {
        if (r + 1 < n) {
          triangles_.emplace_back(id(r, s), id(r, s + 1), id(r + 1, s + 1));
          triangles_.emplace_back(id(r, s), id(r + 1, s + 1), id(r + 1, s));
        } else {
          triangles_.emplace_back(id(r, s), id(r, s + 1), pole);
        }
      }
  }
  if (spec.shape == Shape::semisphere && spec.bending > 0)
    models::massspring::add_bending(l, triangles_, spec.bending * spec.material.k, spec.bending * spec.material.b);
  sim_ = std::make_unique<models::massspring::Simulator>(l, spec.options);
  substeps_ = sim_->substeps();
  if (substeps_ > 1) {
    // touch() takes the substeps itself, to solve the contact in each.
    models::massspring::Options o = spec.options;
    o.dt /= substeps_;
    sim_ = std::make_unique<models::massspring::Simulator>(std::move(l), o);
  }
  state_ = models::massspring::rest_state(sim_->lattice());
  mesh_ = std::make_unique<MeshProxy>(triangles_, sim_->lattice().size());
}

Eigen::AlignedBox3d ElasticSurface::reach() const {
  const Eigen::Vector3d& c = spec_.centre;
  if (spec_.shape == Shape::sheet) {
    const double half = 0.5 * spec_.size;
    return {c - Eigen::Vector3d::Constant(half), c + Eigen::Vector3d(half, half, 0.1 * half)};
  }
  const double out = 1.05 * spec_.size;
  return {c - Eigen::Vector3d(out, out, 0), c + Eigen::Vector3d::Constant(out)};
}

Eigen::Vector3d ElasticSurface::proxy() const {
  return contact_.face < 0 ? last_hip_ : mesh_->point(state_.x, contact_);
}

Touch ElasticSurface::touch(double dt, const Eigen::Vector3d& hip, bool grab) {
  need(std::isfinite(dt) && std::abs(dt - spec_.options.dt) <= 1e-9 * spec_.options.dt,
       "touch dt must equal the behavior step options.dt");
  need(hip.allFinite(), "the haptic point must be finite");
  loads_.clear();
  bool entering = false;  // until the HIP, on its way through the tick, is in
  if (contact_.face < 0 && reach().contains(hip)) {
    if (has_last_) {
      // Only a path that meets the surface's box, then or now, can cross it.
      Eigen::AlignedBox3d path(last_hip_), surface(state_.x.rowwise().minCoeff(), state_.x.rowwise().maxCoeff());
      path.extend(hip);
      surface.extend(Eigen::AlignedBox3d(last_x_.rowwise().minCoeff(), last_x_.rowwise().maxCoeff()));
      if (path.intersects(surface)) contact_ = mesh_->entry(last_x_, state_.x, last_hip_, hip);
      entering = contact_.face >= 0;
    } else {
      // The first HIP seen (a service started with the stylus in the
      // surface) has no path in: it touches at the nearest point.
      const SurfacePoint p = mesh_->closest(state_.x, hip);
      if (mesh_->behind(state_.x, p, hip)) contact_ = p;
    }
    cone_.release();
  }
  const Eigen::Vector3d last = has_last_ ? last_hip_ : hip;
  last_hip_ = hip, last_x_ = state_.x, has_last_ = true;
  // The contact is solved once per substep, with the HIP moving on its
  // straight path through the tick, so that the coupling sees the surface
  // as the integrator moves it.
  const double h = dt / substeps_;
  const Eigen::Vector3d speed = (hip - last) / dt;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::UnitZ();
  SurfacePoint touched;
  std::vector<models::massspring::PointForce> step_loads;
  for (int i = 1; i <= substeps_; ++i) {
    step_loads.clear();
    const Eigen::Vector3d at = last + (hip - last) * (double(i) / substeps_);
    if (entering) entering = (at - proxy()).dot(mesh_->normal(state_.x, contact_)) > 0;
    if (contact_.face >= 0 && !entering) touched = contact_, force += couple(h, at, speed, grab, &n, step_loads);
    sim_->step(state_, step_loads);
    for (models::massspring::PointForce& p : step_loads) loads_.push_back({p.mass, p.force / substeps_});
  }
  force /= substeps_;
  Touch t;
  if (touched.face < 0) return t;
  t.in_contact = contact_.face >= 0 || !force.isZero();
  t.force = force;
  t.normal = n;
  // Depth and secant stiffness against the touched point's rest place.
  const models::massspring::Lattice& l = sim_->lattice();
  const Eigen::Vector3d rest_n = mesh_->normal(l.rest, touched);
  t.depth = std::max(0.0, (mesh_->point(l.rest, touched) - hip).dot(rest_n));
  t.stiffness = t.depth > 1e-9 ? std::max(0.0, force.dot(n)) / t.depth : 0;
  return t;
}

Eigen::Vector3d ElasticSurface::couple(double h, const Eigen::Vector3d& hip, const Eigen::Vector3d& hip_speed,
                                       bool grab, Eigen::Vector3d* normal,
                                       std::vector<models::massspring::PointForce>& loads) {
  const models::massspring::Lattice& l = sim_->lattice();
  const Eigen::Matrix3Xd& x = state_.x;
  const SurfacePoint at = contact_;  // where this substep's force acts
  const Eigen::Vector3i& tri = mesh_->triangle(at.face);
  const Eigen::Vector3d n = mesh_->normal(x, at);
  *normal = n;
  // Where the proxy would be, and how fast it would go, after one
  // symplectic Euler substep with no contact; a load F on it moves it by
  // h^2 F / m and speeds it up by h F / m, m its mass.
  Eigen::Vector3d free = Eigen::Vector3d::Zero(), speed = Eigen::Vector3d::Zero();
  double give = 0;  // 1 / kg: the touched point's inverse mass
  for (int k = 0; k < 3; ++k) {
    const int i = tri[k];
    const double b = at.bary[k], inv = l.anchored[i] ? 0 : 1 / l.mass[i];
    const Eigen::Vector3d pull = inv * sim_->spring_force(i, state_);
    free += b * (x.col(i) + h * state_.v.col(i) + h * h * pull);
    speed += b * (state_.v.col(i) + h * pull);
    give += b * b * inv;
  }
  // The coupling, a spring-damper between proxy and HIP (Colgate et al.
  // 1995), solved at the end of the substep with the surface's answer to
  // it. Its damper stops a surface from bouncing off the stylus; it is
  // critical for the touched point's mass, or less where that would make
  // the first instant of contact kick harder than the spring times the
  // HIP's motion.
  const double k = spec_.contact_stiffness, a = h * h * give, a_v = h * give;
  double damper = give > 0 ? 2 * std::sqrt(k / give) : 0;
  if (k * a_v < 1 / h) damper = std::min(damper, (1 - 1e-9) * k * k * a / (1 / h - k * a_v));
  // The damper acts along the normal only: sideways, friction is what
  // drags, and the proxy may slide over material that moves.
  const Eigen::Vector3d gap = free - hip;
  const double push = (k * gap.dot(n) + damper * (speed - hip_speed).dot(n)) / (1 + k * a + damper * a_v);
  Eigen::Vector3d force = push * n + k * (gap - gap.dot(n) * n) / (1 + k * a);
  if (!grab && push <= 0 && (hip - mesh_->point(x, at)).dot(n) > 0) {
    // The HIP is back outside, and the surface does not come after it: the
    // contact ends, and the next entry is looked for from here.
    last_hip_ = hip, last_x_ = x;
    contact_ = {};
    cone_.release();
    return Eigen::Vector3d::Zero();
  }
  if (!grab && push <= 0) {
    // The surface moves away faster than the HIP follows: it does not
    // pull (the contact is one-sided), and it is still touched.
    cone_.release();
    force.setZero();
  } else if (!grab) {
    const haptic::FrictionCone::Grip g = cone_.grip(force, n);
    force = g.force;
    if (g.keep < 1) {
      // Slip: the proxy moves over the faces by the share of the HIP's
      // tangential offset that friction does not hold.
      Eigen::Vector3d t = hip - free;
      t -= t.dot(n) * n;
      contact_ = mesh_->nearest(x, at, mesh_->point(x, at) + (1 - g.keep) * t);
    }
  }
  for (int v = 0; v < 3; ++v) loads.push_back({tri[v], -at.bary[v] * force});
  return force;
}

}  // namespace hcosim::models::deformable
