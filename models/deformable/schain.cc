#include "models/deformable/schain.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::deformable {

namespace {

void need_chain(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("schain: " + what);
}

void check(const ChainMaterial& m) {
  need_chain(m.stiffness > 0 && std::isfinite(m.stiffness), "stiffness must be finite and > 0");
  for (double r : {m.stretch, m.compress, m.shear})
    need_chain(r > 0 && r < 1, "stretch, compress and shear must be in (0, 1)");
}

}  // namespace

Eigen::Vector3d ChainLattice::rest(int e) const {
  const int i = e % nx, j = (e / nx) % ny, k = e / (nx * ny);
  return origin + spacing * Eigen::Vector3d(i, j, k);
}

ChainLattice make_chain_box(int nx, int ny, int nz, double spacing, const ChainMaterial& m) {
  need_chain(nx >= 2 && ny >= 2 && nz >= 2, "a chain box needs at least 2 x 2 x 2 elements");
  need_chain(spacing > 0 && std::isfinite(spacing), "spacing must be finite and > 0");
  check(m);
  ChainLattice l;
  l.nx = nx, l.ny = ny, l.nz = nz, l.spacing = spacing;
  l.material.assign(l.size(), m);
  l.anchored.assign(l.size(), 0);
  l.present.assign(l.size(), 1);
  return l;
}

SChain::SChain(ChainLattice lattice, double relax_rate, double limit_stiffness)
    : lat_(std::move(lattice)), relax_rate_(relax_rate), limit_stiffness_(limit_stiffness) {
  need_chain(lat_.nx >= 2 && lat_.ny >= 2 && lat_.nz >= 2, "a chain lattice needs at least 2 x 2 x 2 elements");
  need_chain(lat_.spacing > 0 && std::isfinite(lat_.spacing), "spacing must be finite and > 0");
  need_chain(int(lat_.material.size()) == lat_.size() && int(lat_.anchored.size()) == lat_.size() &&
                 int(lat_.present.size()) == lat_.size(),
             "material, anchored and present need one entry per element");
  for (const ChainMaterial& m : lat_.material) check(m);
  on_surface_.assign(lat_.size(), 0);
  for (int k = 0; k < lat_.nz; ++k)
    for (int j = 0; j < lat_.ny; ++j)
      for (int i = 0; i < lat_.nx; ++i) {
        const int e = lat_.index(i, j, k);
        if (!lat_.present[e]) continue;
        const bool border = i == 0 || j == 0 || k == 0 || i == lat_.nx - 1 || j == lat_.ny - 1 || k == lat_.nz - 1;
        if (border || !lat_.present[e - 1] || !lat_.present[e + 1] || !lat_.present[e - lat_.nx] ||
            !lat_.present[e + lat_.nx] || !lat_.present[e - lat_.nx * lat_.ny] || !lat_.present[e + lat_.nx * lat_.ny])
          on_surface_[e] = 1, surface_.push_back(e);
      }
  need_chain(!surface_.empty(), "a chain lattice needs at least one element present");
  need_chain(relax_rate > 0 && std::isfinite(relax_rate), "relax_rate must be finite and > 0");
  need_chain(limit_stiffness >= 0 && std::isfinite(limit_stiffness), "limit_stiffness must be finite and >= 0");
  u_.assign(lat_.size(), Eigen::Vector3d::Zero());
  in_moved_.assign(lat_.size(), 0);
  visit_.assign(lat_.size(), 0);
  queued_.assign(lat_.size(), 0);
}

void SChain::mark(int e) {
  if (!in_moved_[e]) in_moved_[e] = 1, moved_.push_back(e);
}

bool SChain::enforce(int from, int n, int axis, int side, bool* blocked) {
  const ChainMaterial &a = lat_.material[from], &b = lat_.material[n];
  const double s = lat_.spacing;
  const double stretch = std::min(a.stretch, b.stretch) * s, compress = std::min(a.compress, b.compress) * s;
  const double shear = std::min(a.shear, b.shear) * s;
  Eigen::Vector3d d = u_[n] - u_[from];
  const Eigen::Vector3d before = d;
  for (int c = 0; c < 3; ++c) {
    if (c == axis) {
      // Apart along the link is side * d > 0.
      const double lo = side > 0 ? -compress : -stretch, hi = side > 0 ? stretch : compress;
      d[c] = std::clamp(d[c], lo, hi);
    } else {
      d[c] = std::clamp(d[c], -shear, shear);
    }
  }
  // Violations below a nanometre per centimetre are rounding, not strain.
  if ((d - before).cwiseAbs().maxCoeff() <= 1e-7 * s) return false;
  if (lat_.anchored[n]) {
    *blocked = true;
    return false;
  }
  undo_.emplace_back(n, u_[n]);
  u_[n] = u_[from] + d;
  return true;
}

bool SChain::propagate(int contact, const Eigen::Vector3d& u, int* count) {
  ++stamp_;
  undo_.clear();
  undo_.emplace_back(contact, u_[contact]);
  u_[contact] = u;
  visit_[contact] = stamp_;
  queue_.assign(1, contact);
  const int stride[3] = {1, lat_.nx, lat_.nx * lat_.ny};
  const int dims[3] = {lat_.nx, lat_.ny, lat_.nz};
  bool blocked = false;
  // Breadth first from the contact. An element moves again when a later
  // neighbour pulls it (links between materials of different ranges need
  // that); the contact never moves, its neighbours give way to it. The work is capped at 64 moves per
  // element reached, far above what the tests and benchmark need.
  std::size_t reached = 1;
  for (std::size_t q = 0; q < queue_.size() && !blocked && q < 64 * reached; ++q) {
    const int e = queue_[q];
    queued_[e] = 0;
    const int at[3] = {e % lat_.nx, (e / lat_.nx) % lat_.ny, e / (lat_.nx * lat_.ny)};
    for (int axis = 0; axis < 3; ++axis)
      for (const int side : {-1, 1}) {
        const int c = at[axis] + side;
        if (c < 0 || c >= dims[axis]) continue;
        const int n = e + side * stride[axis];
        if (!lat_.present[n]) continue;
        if (n == contact) {
          // The contact is held: it is e that must give way to it.
          if (enforce(n, e, axis, -side, &blocked) && !queued_[e]) queued_[e] = 1, queue_.push_back(e);
          continue;
        }
        if (!enforce(e, n, axis, side, &blocked)) continue;
        if (visit_[n] != stamp_) visit_[n] = stamp_, ++reached;
        if (!queued_[n]) queued_[n] = 1, queue_.push_back(n);
      }
  }
  for (std::size_t q = 0; q < queue_.size(); ++q) queued_[queue_[q]] = 0;
  *count = int(reached);
  return !blocked;
}

void SChain::undo() {
  for (auto it = undo_.rbegin(); it != undo_.rend(); ++it) u_[it->first] = it->second;
  undo_.clear();
}

int SChain::tick(double dt, int contact, const Eigen::Vector3d& target) {
  need_chain(dt > 0 && std::isfinite(dt), "dt must be finite and > 0");
  need_chain(contact >= -1 && contact < lat_.size() && (contact < 0 || lat_.present[contact]),
             "contact element " + std::to_string(contact) + " is not in the lattice");
  need_chain(contact < 0 || target.allFinite(), "the contact target must be finite");
  // Elastic relaxation: every link's allowed box contains zero difference,
  // so scaling all displacements down never violates a link.
  const double keep = std::exp(-relax_rate_ * dt), eps = 1e-9 * lat_.spacing;
  std::size_t w = 0;
  for (const int e : moved_) {
    u_[e] *= keep;
    if (u_[e].norm() < eps) {
      u_[e].setZero(), in_moved_[e] = 0;
      continue;
    }
    moved_[w++] = e;
  }
  moved_.resize(w);
  gap_.setZero();
  if (contact < 0 || lat_.anchored[contact]) return 0;
  // The contacted element follows the haptic point as far as the anchors
  // let it: a move that would need an anchored element to move is cut back
  // (bisection on the way from the relaxed position to the target).
  const Eigen::Vector3d from = u_[contact], to = target - lat_.rest(contact);
  int count = 0;
  if (!propagate(contact, to, &count)) {
    undo();
    double lo = 0, hi = 1;
    for (int it = 0; it < 12; ++it) {  // to 1/4096 of the move
      const double mid = 0.5 * (lo + hi);
      (propagate(contact, from + mid * (to - from), &count) ? lo : hi) = mid;
      undo();
    }
    propagate(contact, from + lo * (to - from), &count);
  }
  for (const auto& [e, old] : undo_) mark(e);
  gap_ = to - u_[contact];
  return count;
}

Eigen::Vector3d SChain::force() const {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const int e : moved_) f -= lat_.material[e].stiffness * u_[e];
  return f - limit_stiffness_ * gap_;
}

int SChain::nearest_surface(const Eigen::Vector3d& p) const {
  if (!p.allFinite()) return -1;
  const Eigen::Vector3d g = (p - lat_.origin) / lat_.spacing;
  const int dims[3] = {lat_.nx, lat_.ny, lat_.nz};
  int at[3];
  for (int c = 0; c < 3; ++c) {
    if (g[c] < -1 || g[c] > dims[c]) return -1;
    at[c] = std::clamp(int(std::lround(g[c])), 0, dims[c] - 1);
  }
  // The nearest grid node, when it is on the surface (p on or near it);
  // otherwise the nearest surface element by search.
  if (const int e = lat_.index(at[0], at[1], at[2]); on_surface_[e]) return e;
  int best = -1;
  double dist = 1e300;
  for (const int e : surface_)
    if (const double d = (lat_.rest(e) - p).squaredNorm(); d < dist) dist = d, best = e;
  return best;
}

}  // namespace hcosim::models::deformable
