// Time integrators of the behavior model and their stability conditions.
//
// For the undamped oscillator x'' = -w^2 x:
//   symplectic_euler  v = (v + h a(x, v)) e^(-h drag/m); x += h v.
//                     Stable iff w h < 2.
//   velocity_verlet   half-kick, drift, half-kick, inside half-steps of the
//                     exact drag flow; spring dampers act at the half-step
//                     velocity. Stable iff w h < 2.
//   rk4               classical Runge-Kutta 4, drag included. Stable on the
//                     imaginary axis up to w h < 2.83; on the left half disc
//                     up to 2.61.
//   implicit_euler    (M + h C + h^2 K) dv = h (f - h K v), K and C
//                     linearised at x (Baraff-Witkin). Unconditionally stable;
//                     damps each mode by 1 / sqrt(1 + (w h)^2) per step.
//   local_global      Liu et al. 2013: implicit Euler solved by alternating
//                     spring-direction projection and a prefactored Cholesky
//                     solve of (M + h D + h^2 L). Unconditionally stable;
//                     spring dampers act on the whole relative velocity.
// With an explicit damping rate c (1/s: spring dampers, plus drag for rk4)
// the explicit bounds become h < C / (c + sqrt(c^2 + 4 w^2)), C = 4 for
// symplectic_euler and velocity_verlet (exact for the former), 5.2 for rk4.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "models/massspring/lattice.h"

namespace hcosim::models::massspring {

enum class Integrator { symplectic_euler, velocity_verlet, rk4, implicit_euler, local_global };

const char* name(Integrator integrator);
bool is_explicit(Integrator integrator);

// Upper bounds on the lattice's highest eigenfrequency (rad/s, sqrt of the
// largest eigenvalue of M^-1 K) and spring damping rate (1/s, largest
// eigenvalue of M^-1 D), by Gershgorin's theorem on the free masses or on
// the springs, whichever is tighter; and the largest drag rate drag / m.
// They hold in every configuration where no spring is compressed below
// half its rest length: a spring's stiffness then never exceeds k in any
// direction, so K <= L (x) I for the k-weighted graph Laplacian L.
// Quartets add their Gauss-Newton stiffness's bound, which holds while no
// hinge's triangle's height falls below half its rest and no tetrahedron's
// face grows past twice its rest area.
// quartet_omega_max and quartet_damping_max bound the quartets' part
// alone: local_global steps quartets explicitly beside its implicit springs.
struct Spectrum {
  double omega_max = 0;
  double damping_max = 0;
  double drag_max = 0;
  double quartet_omega_max = 0;
  double quartet_damping_max = 0;
};
Spectrum bound_spectrum(const Lattice& lattice);

// bound_spectrum in parts, for a simulator that counts a quartet only
// while it can act (a volume floor near its rest, simulator.cc): the
// springs' and the drag's bounds, and the Gershgorin rows of the counted
// quartets, one per mass ((rad/s)^2 for the stiffness, 1/s for the
// damping). A quartet's share of the rows is quartet_share's.
struct SpectrumParts {
  double spring_k = 0;  // (rad/s)^2
  double spring_b = 0;  // 1/s
  double drag_max = 0;  // 1/s
  Eigen::VectorXd quartet_k, quartet_b;
  // The spectrum these parts bound.
  Spectrum spectrum() const;
  // The same with the quartets' largest rows given (a simulator's rows
  // with more quartets counted than these parts have).
  Spectrum with_rows(double quartet_k_max, double quartet_b_max) const;
};
// `counted` has one flag per quartet of the lattice.
SpectrumParts spectrum_parts(const Lattice& lattice, const std::vector<std::uint8_t>& counted);

// Quartet q's share of SpectrumParts' rows at its corners i, j, k, l.
struct QuartetShare {
  double k[4] = {0, 0, 0, 0};
  double b[4] = {0, 0, 0, 0};
};
QuartetShare quartet_share(const Lattice& lattice, const Quartet& quartet);

// Fraction of the stability limit that stable_step allows. The bounds are
// already above the true spectrum; the margin keeps the highest mode's
// amplitude error of symplectic_euler, 1 / sqrt(1 - (w h / 2)^2), below 3.2.
constexpr double kStableMargin = 0.95;

// Largest step (s) at which `integrator` is stable for `spectrum`, times
// kStableMargin; +infinity for implicit_euler, and for local_global on a
// lattice without quartets (with them, symplectic_euler's limit on the
// quartets' bounds alone).
double stable_step(Integrator integrator, const Spectrum& spectrum);

}  // namespace hcosim::models::massspring
