#include "models/massspring/integrator.h"

#include <cmath>
#include <limits>

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

}  // namespace

// Gershgorin's bound on the largest eigenvalue of M^-1 H, H the sum over
// quartets of w g g^T (g: the measure's gradient at rest, anchored corners
// left out), blocks w |g_p| |g_q| / sqrt(m_p m_q). An angle's gradient
// scales as one over a triangle's height, a volume's as a face's area:
// times 4 keeps the bound while heights stay above half their rest and
// faces below twice their rest area.
QuartetShare quartet_share(const Lattice& l, const Quartet& h) {
  Eigen::Vector3d g[4];
  measure(h, l.rest, g);
  const int c[4] = {h.i, h.j, h.k, h.l};
  double scaled[4], sum = 0;
  for (int q = 0; q < 4; ++q) sum += scaled[q] = l.anchored[c[q]] ? 0 : g[q].norm() / std::sqrt(l.mass[c[q]]);
  QuartetShare share;
  for (int q = 0; q < 4; ++q) {
    share.k[q] = 4 * h.stiffness * scaled[q] * sum;
    share.b[q] = 4 * h.b * scaled[q] * sum;
  }
  return share;
}

SpectrumParts spectrum_parts(const Lattice& l, const std::vector<std::uint8_t>& counted) {
  SpectrumParts p;
  p.spring_k = laplacian_bound(l, [](const Spring& s) { return s.k; });
  p.spring_b = laplacian_bound(l, [](const Spring& s) { return s.b; });
  for (int i = 0; i < l.size(); ++i)
    if (!l.anchored[i]) p.drag_max = std::max(p.drag_max, l.drag / l.mass[i]);
  p.quartet_k = p.quartet_b = Eigen::VectorXd::Zero(l.size());
  for (std::size_t q = 0; q < l.quartets.size(); ++q) {
    if (!counted[q]) continue;
    const Quartet& h = l.quartets[q];
    const QuartetShare share = quartet_share(l, h);
    const int c[4] = {h.i, h.j, h.k, h.l};
    for (int k = 0; k < 4; ++k) p.quartet_k[c[k]] += share.k[k], p.quartet_b[c[k]] += share.b[k];
  }
  return p;
}

Spectrum SpectrumParts::spectrum() const {
  return with_rows(quartet_k.size() ? quartet_k.maxCoeff() : 0.0, quartet_b.size() ? quartet_b.maxCoeff() : 0.0);
}

Spectrum SpectrumParts::with_rows(double qk, double qb) const {
  Spectrum sp;
  sp.quartet_omega_max = std::sqrt(qk);
  sp.quartet_damping_max = qb;
  sp.omega_max = std::sqrt(spring_k + qk);
  sp.damping_max = spring_b + qb;
  sp.drag_max = drag_max;
  return sp;
}

Spectrum bound_spectrum(const Lattice& l) {
  return spectrum_parts(l, std::vector<std::uint8_t>(l.quartets.size(), 1)).spectrum();
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
