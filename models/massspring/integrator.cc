#include "models/massspring/integrator.h"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "models/massspring/quartet.h"

namespace hcosim::models::massspring {

const char* name(Integrator i) {
  switch (i) {
    case Integrator::symplectic_euler:
      return "symplectic_euler";
    case Integrator::velocity_verlet:
      return "velocity_verlet";
    case Integrator::rk4:
      return "rk4";
    case Integrator::implicit_euler:
      return "implicit_euler";
    case Integrator::local_global:
      return "local_global";
  }
  return "?";
}

Integrator parse_integrator(const std::string& s) {
  for (Integrator i : {Integrator::symplectic_euler, Integrator::velocity_verlet, Integrator::rk4,
                       Integrator::implicit_euler, Integrator::local_global})
    if (s == name(i)) return i;
  throw std::invalid_argument("unknown integrator '" + s +
                              "' (expected symplectic_euler, velocity_verlet, rk4, implicit_euler or local_global)");
}

bool is_explicit(Integrator i) { return i != Integrator::implicit_euler && i != Integrator::local_global; }

namespace {

// Upper bound on the largest eigenvalue of M^-1 L for the Laplacian L of the
// lattice's springs weighted by `w`, anchored masses removed: the smaller of
// Gershgorin's bound on the masses (rows of M^-1/2 L M^-1/2) and on the
// springs (rows of W^1/2 B^T M^-1 B W^1/2, which has the same nonzero
// eigenvalues). The second is much tighter at a mass with many springs,
// e.g. a semi-sphere's pole: deg + neighbour deg instead of 2 deg.
template <class Weight>
double laplacian_bound(const Lattice& l, Weight&& w) {
  const int n = l.size();
  // Per mass: sum of w / m over its springs (+ the coupling term), and of sqrt(w).
  Eigen::VectorXd row = Eigen::VectorXd::Zero(n), root = Eigen::VectorXd::Zero(n);
  for (const Spring& s : l.springs) {
    const double mi = l.mass[s.i], mj = l.mass[s.j], ws = w(s), off = 1 / std::sqrt(mi * mj);
    row[s.i] += ws * (1 / mi + (l.anchored[s.j] ? 0 : off));
    row[s.j] += ws * (1 / mj + (l.anchored[s.i] ? 0 : off));
    root[s.i] += std::sqrt(ws), root[s.j] += std::sqrt(ws);
  }
  double by_mass = 0, by_spring = 0;
  for (int i = 0; i < n; ++i)
    if (!l.anchored[i]) by_mass = std::max(by_mass, row[i]);
  for (const Spring& s : l.springs) {
    const double ri = l.anchored[s.i] ? 0 : root[s.i] / l.mass[s.i];
    const double rj = l.anchored[s.j] ? 0 : root[s.j] / l.mass[s.j];
    by_spring = std::max(by_spring, std::sqrt(w(s)) * (ri + rj));
  }
  return std::min(by_mass, by_spring);
}

// Gershgorin's bound on the largest eigenvalue of M^-1 H, H the sum over
// quartets of w g g^T (g: the measure's gradient at rest, anchored corners
// left out), blocks w |g_p| |g_q| / sqrt(m_p m_q). An angle's gradient
// scales as one over a triangle's height, a volume's as a face's area:
// times 4 keeps the bound while heights stay above half their rest and
// faces below twice their rest area.
template <class Weight>
double quartet_bound(const Lattice& l, Weight&& w) {
  Eigen::VectorXd row = Eigen::VectorXd::Zero(l.size());
  for (const Quartet& h : l.quartets) {
    Eigen::Vector3d g[4];
    measure(h, l.rest, g);
    const int c[4] = {h.i, h.j, h.k, h.l};
    double scaled[4], sum = 0;
    for (int q = 0; q < 4; ++q) sum += scaled[q] = l.anchored[c[q]] ? 0 : g[q].norm() / std::sqrt(l.mass[c[q]]);
    for (int q = 0; q < 4; ++q) row[c[q]] += 4 * w(h) * scaled[q] * sum;
  }
  return row.size() ? row.maxCoeff() : 0.0;
}

}  // namespace

Spectrum bound_spectrum(const Lattice& l) {
  Spectrum sp;
  const double quartet_k = quartet_bound(l, [](const Quartet& h) { return h.stiffness; });
  sp.quartet_omega_max = std::sqrt(quartet_k);
  sp.quartet_damping_max = quartet_bound(l, [](const Quartet& h) { return h.b; });
  sp.omega_max = std::sqrt(laplacian_bound(l, [](const Spring& s) { return s.k; }) + quartet_k);
  sp.damping_max = laplacian_bound(l, [](const Spring& s) { return s.b; }) + sp.quartet_damping_max;
  for (int i = 0; i < l.size(); ++i)
    if (!l.anchored[i]) sp.drag_max = std::max(sp.drag_max, l.drag / l.mass[i]);
  return sp;
}

double stable_step(Integrator i, const Spectrum& sp) {
  if (i == Integrator::implicit_euler) return std::numeric_limits<double>::infinity();
  // local_global: springs implicit, quartets' forces explicit (symplectic).
  const bool quartets_only = i == Integrator::local_global;
  // symplectic_euler and velocity_verlet integrate drag exactly; rk4 does not.
  const double c = quartets_only ? sp.quartet_damping_max : sp.damping_max + (i == Integrator::rk4 ? sp.drag_max : 0);
  const double w = quartets_only ? sp.quartet_omega_max : sp.omega_max;
  const double rate = c + std::sqrt(c * c + 4 * w * w);
  if (rate <= 0) return std::numeric_limits<double>::infinity();
  return kStableMargin * (i == Integrator::rk4 ? 5.2 : 4.0) / rate;
}

}  // namespace hcosim::models::massspring
