#include "massspring/integrator.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace hcosim::massspring {

const char* name(Integrator i) {
  switch (i) {
    case Integrator::symplectic_euler: return "symplectic_euler";
    case Integrator::velocity_verlet: return "velocity_verlet";
    case Integrator::rk4: return "rk4";
    case Integrator::implicit_euler: return "implicit_euler";
    case Integrator::local_global: return "local_global";
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

Spectrum bound_spectrum(const Lattice& l) {
  const int n = l.size();
  // Row sums of M^-1/2 L M^-1/2 for the k- and b-weighted graph Laplacians.
  Eigen::VectorXd k_row = Eigen::VectorXd::Zero(n), b_row = Eigen::VectorXd::Zero(n);
  for (const Spring& s : l.springs) {
    const double mi = l.mass[s.i], mj = l.mass[s.j];
    const double off = 1.0 / std::sqrt(mi * mj);
    k_row[s.i] += s.k * (1 / mi + (l.anchored[s.j] ? 0 : off));
    k_row[s.j] += s.k * (1 / mj + (l.anchored[s.i] ? 0 : off));
    b_row[s.i] += s.b * (1 / mi + (l.anchored[s.j] ? 0 : off));
    b_row[s.j] += s.b * (1 / mj + (l.anchored[s.i] ? 0 : off));
  }
  Spectrum sp;
  for (int i = 0; i < n; ++i) {
    if (l.anchored[i]) continue;
    sp.omega_max = std::max(sp.omega_max, std::sqrt(k_row[i]));
    sp.damping_max = std::max(sp.damping_max, b_row[i] + l.drag / l.mass[i]);
  }
  return sp;
}

double stable_step(Integrator i, const Spectrum& sp) {
  if (!is_explicit(i)) return std::numeric_limits<double>::infinity();
  const double c = sp.damping_max, w = sp.omega_max;
  const double rate = c + std::sqrt(c * c + 4 * w * w);
  if (rate <= 0) return std::numeric_limits<double>::infinity();
  return 0.9 * (i == Integrator::rk4 ? 5.2 : 4.0) / rate;
}

}  // namespace hcosim::massspring
