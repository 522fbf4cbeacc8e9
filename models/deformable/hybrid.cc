#include "models/deformable/hybrid.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "models/deformable/surface.h"

namespace hcosim::models::deformable {

namespace {

// The visual vertex nearest a point (rest, world).
int nearest_vertex(const Eigen::Matrix3Xd& vertices, const Eigen::Vector3d& p) {
  int v = 0;
  (vertices.colwise() - p).colwise().squaredNorm().minCoeff(&v);
  return v;
}

// N: the S-Chain's force along n with element e pressed `depth` along -n
// and held until its chains have relaxed: one tick long enough (1 s)
// that the press is its steady state. Leaves the chains at rest.
double chain_press(SChain& chain, int e, const Eigen::Vector3d& n, double depth) {
  const Eigen::Vector3d rest = chain.lattice().rest(e);
  chain.tick(1, e, rest - depth * n);
  const double f = chain.force().dot(n);
  chain.tick(1, -1, rest);
  return f;
}

}  // namespace

Hybrid::Hybrid(const HybridSpec& spec, const MapSource& map, const GainSource& gain)
    : spec_(spec), chains_(hybrid_chains(spec), spec.relax_rate, spec.limit_stiffness), cone_(spec.friction) {
  masses_ = std::make_unique<models::massspring::Simulator>(hybrid_masses(spec), spec.behavior);
  state_ = models::massspring::rest_state(masses_->lattice());
  if (spec.behavior_model != BehaviorModel::springs) {
    models::fem::Options o;
    o.dt = spec.behavior.dt;
    fem_ = std::make_unique<models::fem::Corotational>(hybrid_mesh(spec), spec.fem, o);
  }
  if (spec.behavior_model == BehaviorModel::modal) {
    modal_ = std::make_unique<models::fem::Modal>(*fem_, models::fem::ModalOptions{spec.behavior.dt, spec.modes});
    fem_.reset();
  }
  const Eigen::AlignedBox3d box = rest_box(spec);
  lo_ = box.min(), hi_ = box.max();
  visual_ = hybrid_visual(spec);
  const models::massspring::Voxels voxels = hybrid_voxels(spec);
  const models::massspring::Lattice& lat = masses_->lattice();
  const Cage cage = map_cage(spec, voxels, lat, visual_);
  cage_ = cage.masses;
  if (spec.map == VisualMap::trilinear) {
    weights_ = map_rows(spec, voxels, cage, visual_.vertices);
  } else {
    weights_ = map ? map(cage.rest, cage.triangles, visual_.vertices)
                   : mvc_map(spec, cage.rest, cage.triangles, visual_.vertices);
    check_hybrid(weights_.rows() == visual_.vertices.cols() && weights_.cols() == cage.rest.cols(),
                 "the visual map must have a row per visual vertex and a column per cage vertex");
  }
  gain_ = gain ? gain(spec, weights_) : shared_force_gain(spec, weights_);
  const std::size_t k = gain_.depth.size();
  check_hybrid(k >= 2 && gain_.soft.size() == k && (gain_.stiff.empty() || gain_.stiff.size() == k),
               "the force gain needs two or more depths and a gain at each");
  // What force_scale reads besides the gain: each surface element's
  // S-Chain force at the gain's depths, pressed along the normal of the
  // visual vertex nearest it.
  const Eigen::Matrix3Xd normals = vertex_normals(visual_.vertices, visual_.triangles);
  SChain chain(chains_.lattice(), spec.relax_rate, spec.limit_stiffness);
  const std::size_t nd = gain_.depth.size();
  chain_force_.assign(chains_.lattice().size() * nd, 0);
  for (const int e : chains_.surface()) {
    if (chains_.lattice().anchored[e]) continue;
    const Eigen::Vector3d n = normals.col(nearest_vertex(visual_.vertices, chains_.lattice().rest(e)));
    for (std::size_t j = 0; j < nd; ++j) chain_force_[e * nd + j] = chain_press(chain, e, n, gain_.depth[j]);
  }
  for (const bool stiff : {false, true})
    std::tie(gain_points_[stiff], gain_elements_[stiff]) =
        find_gain_point(spec, voxels, chains_, stiff && spec.stiff_ratio != 1);
  check_hybrid(gain_elements_[0] >= 0 && gain_elements_[1] >= 0, "no chain element at a gain point");
  columns_ = weights_.cast<float>();
  mesh_ = std::make_unique<MeshProxy>(visual_.triangles, int(visual_.vertices.cols()));
  surface_ = mesh_->grown(visual_.vertices, spec.tip_radius);
  // Cells of about two visual edges: a tick's path meets a few of them.
  double edge = 0;
  for (const Eigen::Vector3i& t : visual_.triangles)
    for (int c = 0; c < 3; ++c) edge += (visual_.vertices.col(t[c]) - visual_.vertices.col(t[(c + 1) % 3])).norm();
  edge /= 3.0 * visual_.triangles.size();
  faces_ = std::make_unique<FaceGrid>(surface_, visual_.triangles, 2 * edge, 1e-9);
  tick_load_.setZero(3, lat.size());
  load_sum_.setZero(3, lat.size());
  listed_.assign(lat.size(), 0);
}

Eigen::Vector3d Hybrid::proxy() const { return contact_.face < 0 ? last_hip_ : mesh_->point(surface_, contact_); }

Touch Hybrid::touch(double dt, const Eigen::Vector3d& hip, bool grab) {
  check_hybrid(dt > 0 && std::isfinite(dt), "dt must be finite and > 0");
  check_hybrid(hip.allFinite(), "the haptic point must be finite");
  const Eigen::Matrix3Xd& rest = surface_;
  if (contact_.face < 0 && reach().contains(hip)) {
    if (has_last_) {
      Eigen::AlignedBox3d path(last_hip_);
      path.extend(hip);
      faces_->near(path, near_);
      contact_ = mesh_->entry(rest, last_hip_, hip, &near_);
    } else {
      // The first HIP seen (a service started with the stylus inside) has
      // no path in: it touches at the surface's nearest point.
      const SurfacePoint p = mesh_->closest(rest, hip);
      if (mesh_->behind(rest, p, hip)) contact_ = p;
    }
    cone_.release();
    if (contact_.face >= 0) follow_ = 1, stored_ = 0;
  }
  const Eigen::Vector3d from = has_last_ ? last_hip_ : hip;  // m: where the HIP was a tick ago
  last_hip_ = hip, has_last_ = true;
  // Only the masses the last touch loaded are cleared: at 100x a whole
  // matrix is 2.3 MB a tick.
  for (const int m : tick_masses_) tick_load_.col(m).setZero(), listed_[m] &= ~kInTick;
  tick_masses_.clear();
  Eigen::Vector3d p, n, offset;
  if (contact_.face >= 0) {
    p = mesh_->point(rest, contact_), n = mesh_->normal(rest, contact_), offset = hip - p;
    if (!grab && offset.dot(n) > 0) contact_ = {}, cone_.release();  // back outside
  }
  if (contact_.face < 0) {
    chains_.tick(dt, -1, hip);
    return {};
  }
  // The chain element nearest the proxy, moved by the HIP's offset from it.
  const int e = chains_.nearest_surface(p);
  chains_.tick(dt, e, chains_.lattice().rest(e) + offset);
  // The chains' force at the behavior model's stiffness for that press
  // (the offset, not how far the chains let the element go: a stiff side's
  // short ranges stop it against the anchors, and the rest is a wall).
  const bool stiff = chains_.lattice().material[e].stiffness > spec_.chain.stiffness;
  const double depth = offset.norm();
  Eigen::Vector3d force = follow_ * force_scale(e, depth, stiff) * chains_.force();
  const SurfacePoint at = contact_;  // where this tick's force acts
  if (!grab && force.dot(n) <= 0) {
    force.setZero();  // chains that do not push do not pull either
  } else if (!grab) {
    // Friction holds the proxy, or lets it slide over the faces by the
    // share of the offset it does not hold.
    const haptic::FrictionCone::Grip g = cone_.grip(force, n);
    force = g.force;
    if (g.keep < 1) contact_ = mesh_->nearest(rest, at, p + (1 - g.keep) * (offset - offset.dot(n) * n));
  }
  // No more energy back than the stylus put in since the contact began:
  // the force is at most kReturn times the work stored (this tick's
  // included) over the offset, so that, backing out, it tapers to nothing
  // with the offset (as the offset to the power kReturn - 1) where the
  // chains' relaxation or follow() would give back more. A force that
  // grows as the offset squared or slower stores at least a third of
  // force times offset and is never cut.
  const double work = -force.dot(hip - from);
  const double most = kReturn * (stored_ + std::max(0.0, work)) / std::max(offset.norm(), 1e-9);
  capped_ = force.norm() > most;
  if (capped_) force *= most / force.norm();
  if (-force.dot(hip - from) < -stored_) force *= stored_ / force.dot(hip - from);
  stored_ = std::max(0.0, stored_ - force.dot(hip - from));
  // The behavior model takes the opposite, from the visual vertices of the
  // proxy's face through the map's weights (whose rows sum to one).
  const Eigen::Vector3i& tri = mesh_->triangle(at.face);
  for (int k = 0; k < 3; ++k)
    for (Weights::InnerIterator w(weights_, tri[k]); w; ++w) {
      const int m = cage_[w.col()];
      if (!(listed_[m] & kInTick)) listed_[m] |= kInTick, tick_masses_.push_back(m);
      tick_load_.col(m) -= at.bary[k] * w.value() * force;
    }
  for (const int m : tick_masses_) {
    if (!(listed_[m] & kInSum)) listed_[m] |= kInSum, sum_masses_.push_back(m);
    load_sum_.col(m) += tick_load_.col(m);
  }
  ++load_ticks_;
  Touch t;
  t.in_contact = true;
  t.force = force;
  t.normal = n;
  t.depth = std::max(0.0, -offset.dot(n));
  t.stiffness = t.depth > 1e-9 ? std::max(0.0, force.dot(n)) / t.depth : 0;
  return t;
}

double Hybrid::force_scale(int e, double depth, bool stiff) const {
  const int side = stiff && !gain_.stiff.empty() ? 1 : 0;
  // The S-Chain's steady force here, or, at an element it has none for
  // (anchored), at the side's gain point.
  const std::size_t nd = gain_.depth.size();
  double chain = power_law(gain_.depth, &chain_force_[std::size_t(e) * nd], depth);
  if (!(chain > 0)) chain = power_law(gain_.depth, &chain_force_[std::size_t(gain_elements_[side]) * nd], depth);
  if (!(chain > 0)) return 1;
  // The drawn surface's compliance at the proxy, from its face's vertices'.
  double ratio = 1;
  if (gain_.compliance.size() == std::size_t(visual_.vertices.cols())) {
    const Eigen::Vector3i& face = mesh_->triangle(contact_.face);
    double c = 0;
    for (int k = 0; k < 3; ++k) c += contact_.bary[k] * gain_.compliance[face[k]];
    const double ref = side ? gain_.stiff_compliance : gain_.soft_compliance;
    if (c > 0 && ref > 0) ratio = std::clamp(ref / c, 1 / kPointSpread, kPointSpread);
  }
  return gain_.at(depth, stiff) * ratio / chain;
}

Eigen::Vector3d Hybrid::moved(const SurfacePoint& q) const {
  const models::massspring::Lattice& lat = masses_->lattice();
  const Eigen::Vector3i& tri = mesh_->triangle(q.face);
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int k = 0; k < 3; ++k)
    for (Weights::InnerIterator w(weights_, tri[k]); w; ++w) {
      const int m = cage_[w.col()];
      u += q.bary[k] * w.value() * (state_.x.col(m) - lat.rest.col(m));
    }
  return u;
}

double Hybrid::sunk() const {
  if (contact_.face < 0) return 0;
  const Eigen::Vector3d offset = last_hip_ - mesh_->point(surface_, contact_);
  if (!(offset.norm() > 0)) return 0;
  const Eigen::Vector3d p = mesh_->point(visual_.vertices, contact_), o = offset.normalized();
  // The proxy's own material point, and the one now on the line from the
  // proxy toward the HIP: a press moves the surface sideways too, so the
  // surface drawn there is not the proxy's own, and where the lattice
  // gives way the proxy's goes deeper than the surface on that line.
  const double own = o.dot(moved(contact_));
  SurfacePoint q = contact_;
  Eigen::Vector3d at = p + moved(q);
  for (int k = 0; k < kSunkWalks; ++k) {
    const Eigen::Vector3d aside = (at - p) - (at - p).dot(o) * o;
    if (aside.norm() < 1e-6) break;
    q = mesh_->nearest(visual_.vertices, q, mesh_->point(visual_.vertices, q) - aside);
    at = mesh_->point(visual_.vertices, q) + moved(q);
  }
  return std::max(own, o.dot(at - p));
}

void Hybrid::couple() {
  // follow(): harder while the drawn surface under the stylus has sunk by
  // less than the press's depth, softer while by more.
  if (!modal_ && contact_.face >= 0) {
    const Eigen::Vector3d offset = last_hip_ - proxy();
    const double depth = offset.norm();
    if (depth > kFollowFrom && -offset.dot(mesh_->normal(surface_, contact_)) >= 0.5 * depth) {
      const double dt = spec_.behavior.dt > 0 ? spec_.behavior.dt : 1e-3, s = sunk();
      const double r = std::clamp(s > 0 ? depth / s : 2.0, 0.5, capped_ ? 1.0 : 2.0);
      follow_ = std::clamp(follow_ * std::pow(r, std::min(1.0, dt / kFollowTime)), 1 / kFollowSpread, kFollowSpread);
    }
  }
  loads_.clear();
  if (load_ticks_ > 0) {
    std::sort(sum_masses_.begin(), sum_masses_.end());  // mass order, whatever the order of touches
    for (const int i : sum_masses_) {
      if (!load_sum_.col(i).isZero()) loads_.push_back({i, load_sum_.col(i) / load_ticks_});
      load_sum_.col(i).setZero(), listed_[i] &= ~kInSum;
    }
    sum_masses_.clear();
    load_ticks_ = 0;
  }
}

void Hybrid::integrate() {
  if (modal_) {
    modal_->step(state_, loads_);
    simulated_ = int(state_.x.cols()), substeps_ = 1;
    return;
  }
  if (fem_) {
    fem_->step(state_, loads_);
    simulated_ = int(state_.x.cols()), substeps_ = 1;
    return;
  }
  const models::massspring::StepInfo info = masses_->step(state_, loads_);
  simulated_ = info.simulated, substeps_ = info.substeps;
}

Eigen::Matrix3Xd Hybrid::cage() const {
  const models::massspring::Lattice& lat = masses_->lattice();
  Eigen::Matrix3Xd u(3, cage_.size());
  for (std::size_t v = 0; v < cage_.size(); ++v) u.col(v) = state_.x.col(cage_[v]) - lat.rest.col(cage_[v]);
  return u;
}

Eigen::Matrix3Xd Hybrid::surface_from(const Eigen::Matrix3Xd& u) const {
  return apply_moved(columns_, visual_.vertices, u, spec_.visual_tolerance);
}

}  // namespace hcosim::models::deformable
