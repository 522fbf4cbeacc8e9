#include "models/massspring/simulator_impl.h"

#include <cmath>

namespace hcosim::models::massspring {

void Simulator::Impl::spring_energy(const Eigen::Matrix3Xd& x) {
  for (const int si : springs) {
    const Spring& sp = lat.springs[si];
    const double stretch = (x.col(sp.j) - x.col(sp.i)).norm() - sp.rest;
    spring_elastic[si] = 0.25 * sp.k * stretch * stretch;
  }
  for (const int qi : quartets) quartet_elastic[qi] = 0.5 * quartet_energy(lat.quartets[qi], x);
  for (const int i : masses) {
    elastic[i] = 0;
    for (int k = adj.start[i]; k < adj.start[i + 1]; ++k) elastic[i] += spring_elastic[adj.spring[k]];
    for (int k = quartet_index.start[i]; k < quartet_index.start[i + 1]; ++k)
      elastic[i] += quartet_elastic[quartet_index.quartet[k]];
  }
}

void Simulator::Impl::quartet_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool energy) {
  if (quartets.empty()) return;
  for (const int qi : quartets) {
    const Quartet& e = lat.quartets[qi];
    Eigen::Vector3d fq[4];
    const double d = models::massspring::quartet_forces(e, x, v, fq);
    for (int c = 0; c < 4; ++c) quartet_force.col(4 * qi + c) = fq[c];
    if (energy) quartet_elastic[qi] = 0.25 * e.stiffness * d * d;
  }
  for (const int i : masses)
    for (int k = quartet_index.start[i]; k < quartet_index.start[i + 1]; ++k) {
      const int qi = quartet_index.quartet[k];
      f.col(i) += quartet_force.col(4 * qi + quartet_index.corner[k]);
      if (energy) elastic[i] += quartet_elastic[qi];
    }
}

void Simulator::Impl::forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, bool with_drag) {
  for (const int i : masses) {
    f.col(i) = lat.mass[i] * lat.gravity;
    if (with_drag) f.col(i) -= lat.drag * v.col(i);
  }
  for (const PointForce& p : loads) f.col(p.mass) += p.force;
  if (dampers)
    adaptive ? spring_forces<true, true>(x, v) : spring_forces<true, false>(x, v);
  else
    adaptive ? spring_forces<false, true>(x, v) : spring_forces<false, false>(x, v);
  quartet_forces(x, v, adaptive);
  elastic_fresh = adaptive;
}

template <bool kDampers, bool kEnergy>
void Simulator::Impl::spring_forces(const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  const double* V = v.data();
  double* SF = spring_force.data();
  double* SE = spring_elastic.data();
  for (const int si : springs) {
    const Spring& s = lat.springs[si];
    const int a = 3 * s.i, b = 3 * s.j;
    double u[3];
    const double len = spring_axis(lat, s, x, u);
    const double stretch = len - s.rest;
    double mag = s.k * stretch;
    if (kDampers) mag += s.b * (u[0] * (V[b] - V[a]) + u[1] * (V[b + 1] - V[a + 1]) + u[2] * (V[b + 2] - V[a + 2]));
    SF[3 * si] = mag * u[0], SF[3 * si + 1] = mag * u[1], SF[3 * si + 2] = mag * u[2];
    if (kEnergy) SE[si] = 0.25 * s.k * stretch * stretch;
  }
  double* F = f.data();
  for (const int i : masses) {
    double sum[3] = {0, 0, 0}, e = 0;
    for (int k = adj.start[i]; k < adj.start[i + 1]; ++k) {
      const int si = adj.spring[k];
      const double sign = adj.sign[k];
      sum[0] += sign * SF[3 * si], sum[1] += sign * SF[3 * si + 1], sum[2] += sign * SF[3 * si + 2];
      if (kEnergy) e += SE[si];
    }
    F[3 * i] += sum[0], F[3 * i + 1] += sum[1], F[3 * i + 2] += sum[2];
    if (kEnergy) elastic[i] = e;
  }
}

void Simulator::Impl::symplectic_euler(State& s, double h) {
  forces(s.x, s.v, false);
  for (const int i : masses) {
    s.v.col(i) = (s.v.col(i) + h * inv_mass[i] * f.col(i)) * decay[i];
    s.x.col(i) += h * s.v.col(i);
  }
}

void Simulator::Impl::velocity_verlet(State& s, double h) {
  for (const int i : masses) s.v.col(i) *= half[i];
  forces(s.x, s.v, false);
  for (const int i : masses) {
    s.v.col(i) += 0.5 * h * inv_mass[i] * f.col(i);
    s.x.col(i) += h * s.v.col(i);
  }
  forces(s.x, s.v, false);
  for (const int i : masses) s.v.col(i) = (s.v.col(i) + 0.5 * h * inv_mass[i] * f.col(i)) * half[i];
}

void Simulator::Impl::rk4(State& s, double h) {
  for (const int i : masses) {
    x0.col(i) = s.x.col(i), v0.col(i) = s.v.col(i);
    sx.col(i).setZero(), sv.col(i).setZero();
  }
  static constexpr double share[4] = {1, 2, 2, 1}, reach[3] = {0.5, 0.5, 1.0};
  for (int stage = 0; stage < 4; ++stage) {
    forces(s.x, s.v, true);
    for (const int i : masses) {
      const Eigen::Vector3d kx = s.v.col(i), kv = inv_mass[i] * f.col(i);
      sx.col(i) += share[stage] * kx;
      sv.col(i) += share[stage] * kv;
      if (stage < 3) {
        s.x.col(i) = x0.col(i) + reach[stage] * h * kx;
        s.v.col(i) = v0.col(i) + reach[stage] * h * kv;
      }
    }
  }
  for (const int i : masses) {
    s.x.col(i) = x0.col(i) + h / 6 * sx.col(i);
    s.v.col(i) = v0.col(i) + h / 6 * sv.col(i);
  }
}

}  // namespace hcosim::models::massspring
