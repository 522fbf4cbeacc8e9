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

ElasticSurface::ElasticSurface(const SurfaceSpec& spec) : spec_(spec) {
  need(spec.resolution >= 3 && spec.resolution <= 400, "resolution must be in [3, 400]");
  need(spec.size > 0 && std::isfinite(spec.size), "size must be finite and > 0");
  need(spec.centre.allFinite(), "centre must be finite");
  need(spec.prestretch >= 0 && spec.prestretch < 0.5, "prestretch must be in [0, 0.5)");
  need(spec.tip_radius >= 0 && spec.tip_radius < 0.5 * spec.size, "tip_radius must be in [0, size / 2)");
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
  sim_ = std::make_unique<models::massspring::Simulator>(std::move(l), spec.options);
  state_ = models::massspring::rest_state(sim_->lattice());
}

Eigen::Vector3d ElasticSurface::rest_normal(int v) const {
  if (spec_.shape == Shape::sheet) return Eigen::Vector3d::UnitZ();
  return (sim_->lattice().rest.col(v) - spec_.centre).normalized();
}

bool ElasticSurface::inside(const Eigen::Vector3d& hip) const {
  const Eigen::Vector3d p = hip - spec_.centre;
  if (spec_.shape == Shape::sheet) {
    const double half = 0.5 * spec_.size;  // below the sheet no deeper than that
    return std::abs(p.x()) < half && std::abs(p.y()) < half && p.z() < 0 && p.z() > -half;
  }
  return p.z() > 0 && p.norm() < spec_.size;
}

Eigen::AlignedBox3d ElasticSurface::reach() const {
  const Eigen::Vector3d& c = spec_.centre;
  const Eigen::Vector3d r = Eigen::Vector3d::Constant(spec_.tip_radius);
  if (spec_.shape == Shape::sheet) {
    const double half = 0.5 * spec_.size;
    return {c - Eigen::Vector3d(half, half, half) - r, c + Eigen::Vector3d(half, half, 0) + r};
  }
  return {c - Eigen::Vector3d(spec_.size, spec_.size, 0) - r, c + Eigen::Vector3d::Constant(spec_.size) + r};
}

Touch ElasticSurface::touch(double dt, const Eigen::Vector3d& hip_centre, bool grab) {
  need(std::isfinite(dt) && std::abs(dt - spec_.options.dt) <= 1e-9 * spec_.options.dt,
       "touch dt must equal the behavior step options.dt");
  need(hip_centre.allFinite(), "the haptic point must be finite");
  const models::massspring::Lattice& l = sim_->lattice();
  // The tip sphere's point nearest the surface: its centre less its radius
  // along the rest surface's outward normal there.
  Eigen::Vector3d out = Eigen::Vector3d::UnitZ();
  if (spec_.shape == Shape::semisphere && (hip_centre - spec_.centre).norm() > 0)
    out = (hip_centre - spec_.centre).normalized();
  const Eigen::Vector3d hip = hip_centre - spec_.tip_radius * out;
  if (contact_ < 0 && inside(hip)) {
    // The free vertex nearest the HIP's rest-surface projection.
    double best = 1e300;
    for (int v = 0; v < l.size(); ++v) {
      if (sim_->held(v) || l.anchored[v]) continue;
      const double d = (l.rest.col(v) - hip).squaredNorm();
      if (d < best) best = d, contact_ = v;
    }
    if (contact_ >= 0) sim_->hold(contact_, true);
  } else if (contact_ >= 0 && !grab && (hip - l.rest.col(contact_)).dot(rest_normal(contact_)) > 0) {
    sim_->hold(contact_, false);
    state_.v.col(contact_).setZero();
    contact_ = -1;
  }
  if (contact_ >= 0) {
    state_.v.col(contact_) = (hip - state_.x.col(contact_)) / dt;
    state_.x.col(contact_) = hip;
  }
  sim_->step(state_, {});
  Touch t;
  if (contact_ < 0) return t;
  const Eigen::Vector3d n = rest_normal(contact_);
  t.in_contact = true;
  t.force = sim_->spring_force(contact_, state_);
  t.depth = std::max(0.0, (l.rest.col(contact_) - hip).dot(n));
  t.stiffness = t.depth > 1e-9 ? std::max(0.0, t.force.dot(n)) / t.depth : 0;
  t.normal = n;
  return t;
}

}  // namespace hcosim::models::deformable
