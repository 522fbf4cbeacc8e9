#include "models/deformable/elastic_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "models/massspring/quartet.h"

namespace hcosim::models::deformable {

namespace {

void need_surface(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("elastic surface: " + what);
}

// An untouched surface whose every mass is this close to rest and this
// slow is put at rest and no longer stepped: a nanometre is far below what
// a display or a hand resolves, and a released membrane gets there within
// seconds (its recovery tests need 0.1 mm).
constexpr double kRestOffset = 1e-9;  // m
constexpr double kRestSpeed = 1e-6;   // m/s

// A hemisphere of `radius` over z = 0 whose triangles are near-equal:
// `rings` latitude rings, the base ring first, ring r at polar angle
// (pi/2)(1 - r/rings) with 4 rings sin(polar) masses (at least 3), then the
// pole; each strip between rings zipped by azimuth. Equal counts on every
// ring (a UV sphere) leave slivers at the pole a fifteenth of the base's
// spacing, whose bending stiffness grows as the inverse fourth power of
// their width and would need thousands of substeps.
void dome(int rings, double radius, Eigen::Matrix3Xd& x, std::vector<Eigen::Vector3i>& triangles) {
  std::vector<int> start(rings + 1, 0);
  for (int r = 0; r < rings; ++r) {
    const double polar = M_PI / 2 * (1 - double(r) / rings);
    start[r + 1] = start[r] + std::max(3, int(std::lround(4 * rings * std::sin(polar))));
  }
  const int pole = start[rings];
  x.resize(3, pole + 1);
  for (int r = 0; r < rings; ++r) {
    const double polar = M_PI / 2 * (1 - double(r) / rings);
    const int count = start[r + 1] - start[r];
    for (int s = 0; s < count; ++s) {
      const double az = 2 * M_PI * s / count;
      x.col(start[r] + s) << radius * std::sin(polar) * std::cos(az), radius * std::sin(polar) * std::sin(az),
          radius * std::cos(polar);
    }
  }
  x.col(pole) << 0, 0, radius;
  triangles.clear();
  for (int r = 0; r < rings; ++r) {
    const int na = start[r + 1] - start[r];
    auto a = [&](int i) { return start[r] + i % na; };
    if (r + 1 == rings) {
      for (int i = 0; i < na; ++i) triangles.emplace_back(a(i), a(i + 1), pole);
      break;
    }
    const int nb = start[r + 2] - start[r + 1];
    auto b = [&](int j) { return start[r + 1] + j % nb; };
    // Counter-clockwise seen from outside: lower ring, along it, upper ring.
    for (int i = 0, j = 0; i < na || j < nb;) {
      if (j == nb || (i < na && double(i + 1) / na < double(j + 1) / nb))
        triangles.emplace_back(a(i), a(i + 1), b(j)), ++i;
      else
        triangles.emplace_back(a(i), b(j + 1), b(j)), ++j;
    }
  }
}

}  // namespace

const char* name(Shape s) { return s == Shape::sheet ? "sheet" : "semisphere"; }

ElasticSurface::ElasticSurface(const SurfaceSpec& spec) : spec_(spec), cone_(spec.friction) {
  const auto within = [](const char* field, double v, Range r) {
    need_surface(r.holds(v), std::string(field) + " must be in " + r.text());
  };
  within("resolution", spec.resolution, limits::kResolution);
  within("size", spec.size, limits::kSize);
  need_surface(spec.centre.allFinite(), "centre must be finite");
  within("stiffness", spec.material.k, limits::kSpringStiffness);
  within("damping", spec.material.b, limits::kSpringDamping);
  within("prestretch", spec.prestretch, limits::kPrestretch);
  need_surface(spec.tip_radius >= 0 && spec.tip_radius < 0.5 * spec.size, "tip_radius must be in [0, size / 2)");
  within("bending", spec.bending, limits::kBending);
  within("contact_stiffness", spec.contact_stiffness, limits::kContactStiffness);
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
    Eigen::Matrix3Xd rest;
    dome(n, spec.size, rest, triangles_);
    l = models::massspring::make_shell(rest, triangles_, spec.material);
    l.rest.colwise() += spec.centre;
    for (int v = 0; v < 4 * n; ++v) l.anchored[v] = 1;  // the base ring
  }
  if (spec.bending > 0)
    models::massspring::add_hinges(l, triangles_, spec.bending,
                                   spec.material.k > 0 ? spec.bending * spec.material.b / spec.material.k : 0);
  substeps_ = models::massspring::Simulator(l, spec.options).substeps();
  // touch() takes the substeps itself, to solve the contact in each.
  models::massspring::Options o = spec.options;
  o.dt /= substeps_;
  sim_ = std::make_unique<models::massspring::Simulator>(std::move(l), o);
  state_ = models::massspring::rest_state(sim_->lattice());
  mesh_ = std::make_unique<MeshProxy>(triangles_, sim_->lattice().size());
  rest_ = touched(sim_->lattice().rest);
  last_x_ = rest_;
}

Eigen::Matrix3Xd ElasticSurface::touched(const Eigen::Matrix3Xd& x) const {
  return spec_.tip_radius > 0 ? mesh_->grown(x, spec_.tip_radius) : x;
}

const Eigen::Matrix3Xd& ElasticSurface::touched_now() {
  if (spec_.tip_radius == 0) return state_.x;
  now_ = mesh_->grown(state_.x, spec_.tip_radius);
  return now_;
}

Eigen::AlignedBox3d ElasticSurface::reach() const {
  const Eigen::Vector3d& c = spec_.centre;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(spec_.tip_radius);
  if (spec_.shape == Shape::sheet) {
    const double half = 0.5 * spec_.size;
    return {c - Eigen::Vector3d::Constant(half) - r, c + Eigen::Vector3d(half, half, 0.1 * half) + r};
  }
  const double out = 1.05 * spec_.size;
  return {c - Eigen::Vector3d(out, out, 0) - r, c + Eigen::Vector3d::Constant(out) + r};
}

Eigen::Vector3d ElasticSurface::proxy() const {
  return contact_.face < 0 ? last_hip_ : mesh_->point(touched(state_.x), contact_);
}

Touch ElasticSurface::touch(double dt, const Eigen::Vector3d& hip, bool grab) {
  need_surface(std::isfinite(dt) && std::abs(dt - spec_.options.dt) <= 1e-9 * spec_.options.dt,
               "touch dt must equal the behavior step options.dt");
  need_surface(hip.allFinite(), "the haptic point must be finite");
  loads_.clear();
  bool entering = false;  // until the HIP, on its way through the tick, is in
  const Eigen::Matrix3Xd& now = resting_ ? rest_ : touched_now();
  if (contact_.face < 0 && reach().contains(hip)) {
    if (has_last_) contact_ = mesh_->entry(now, last_hip_, hip);
    entering = contact_.face >= 0;
    if (!entering) {
      // No path in. The first HIP seen, already inside, touches at the
      // surface's nearest point; later, the surface may have come onto
      // the HIP: a membrane that swung past a still stylus, or one that
      // left it a tick ago and is coming back.
      const SurfacePoint p = mesh_->closest(now, hip);
      if (mesh_->behind(now, p, hip) && (!has_last_ || !mesh_->behind(last_x_, p, last_hip_))) contact_ = p;
    }
    cone_.release();
  }
  const Eigen::Vector3d last = has_last_ ? last_hip_ : hip;
  last_hip_ = hip, has_last_ = true;
  if (resting_ && contact_.face < 0) {
    // Untouched and at rest: nothing to step (the surface is rest_, and
    // last_x_ is too).
    state_.t += dt;
    return Touch{};
  }
  resting_ = false;
  last_x_ = now;
  // The contact is solved once per substep, with the HIP moving on its
  // straight path through the tick, so that the coupling sees the surface
  // as the integrator moves it.
  const double h = dt / substeps_;
  const Eigen::Vector3d speed = (hip - last) / dt;
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), n = Eigen::Vector3d::UnitZ();
  SurfacePoint felt_at;
  for (int i = 1; i <= substeps_; ++i) {
    step_loads_.clear();
    const Eigen::Vector3d at = last + (hip - last) * (double(i) / substeps_);
    if (entering) {
      const Eigen::Matrix3Xd& x = touched_now();
      entering = (at - mesh_->point(x, contact_)).dot(mesh_->normal(x, contact_)) > 0;
    }
    if (contact_.face >= 0 && !entering) felt_at = contact_, force += couple(h, at, speed, grab, &n, step_loads_);
    sim_->step(state_, step_loads_);
    for (const models::massspring::PointForce& p : step_loads_) loads_.push_back({p.mass, p.force / substeps_});
  }
  force /= substeps_;
  Touch t;
  if (contact_.face < 0 && (state_.x - sim_->lattice().rest).cwiseAbs().maxCoeff() < kRestOffset &&
      state_.v.cwiseAbs().maxCoeff() < kRestSpeed) {
    // Back at rest: put it there exactly, and stop stepping it until it
    // is touched again.
    state_.x = sim_->lattice().rest;
    state_.v.setZero();
    last_x_ = rest_;
    resting_ = true;
  }
  if (felt_at.face < 0) return t;
  t.in_contact = contact_.face >= 0 || !force.isZero();
  t.force = force;
  t.normal = n;
  // Depth and secant stiffness against the touched point's rest place.
  const Eigen::Vector3d rest_n = mesh_->normal(rest_, felt_at);
  t.depth = std::max(0.0, (mesh_->point(rest_, felt_at) - hip).dot(rest_n));
  t.stiffness = t.depth > 1e-9 ? std::max(0.0, force.dot(n)) / t.depth : 0;
  return t;
}

Eigen::Vector3d ElasticSurface::couple(double h, const Eigen::Vector3d& hip, const Eigen::Vector3d& hip_speed,
                                       bool grab, Eigen::Vector3d* normal,
                                       std::vector<models::massspring::PointForce>& loads) {
  const models::massspring::Lattice& l = sim_->lattice();
  const Eigen::Matrix3Xd& x = touched_now();
  const SurfacePoint at = contact_;  // where this substep's force acts
  const Eigen::Vector3i& tri = mesh_->triangle(at.face);
  const Eigen::Vector3d n = mesh_->normal(x, at);
  *normal = n;
  // Where the proxy would be, and how fast it would go, after one
  // symplectic Euler substep with no contact; a load F on it moves it by
  // h^2 F / m and speeds it up by h F / m, m its mass. (The tip's growth
  // along the normals is taken as fixed over a substep.)
  Eigen::Vector3d free = mesh_->point(x, at), speed = Eigen::Vector3d::Zero();
  double give = 0;  // 1 / kg: the touched point's inverse mass
  for (int k = 0; k < 3; ++k) {
    const int i = tri[k];
    const double b = at.bary[k], inv = l.anchored[i] ? 0 : 1 / l.mass[i];
    const Eigen::Vector3d pull = inv * sim_->spring_force(i, state_);
    free += b * (h * state_.v.col(i) + h * h * pull);
    speed += b * (state_.v.col(i) + h * pull);
    give += b * b * inv;
  }
  // The coupling, a spring-damper between proxy and HIP, solved at the end
  // of the substep with the surface's answer to it. Its damper stops a
  // surface from bouncing off the stylus; it is critical for the touched
  // point's mass, or less where that would make the first instant of
  // contact kick harder than the spring times the HIP's motion.
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
