#include "models/deformable/elastic_surface.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "models/massspring/quartet.h"

namespace hcosim::models::deformable {

namespace {

void need(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("elastic surface: " + what);
}

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

ElasticSurface::ElasticSurface(const SurfaceSpec& spec) : spec_(spec) {
  need(spec.resolution >= 3 && spec.resolution <= 400, "resolution must be in [3, 400]");
  need(spec.size > 0 && std::isfinite(spec.size), "size must be finite and > 0");
  need(spec.centre.allFinite(), "centre must be finite");
  need(spec.prestretch >= 0 && spec.prestretch < 0.5, "prestretch must be in [0, 0.5)");
  need(spec.tip_radius >= 0 && spec.tip_radius < 0.5 * spec.size, "tip_radius must be in [0, size / 2)");
  need(spec.bending >= 0 && std::isfinite(spec.bending), "bending must be finite and >= 0");
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
