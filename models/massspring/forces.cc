#include "models/massspring/forces.h"

#include <algorithm>
#include <cmath>

#include "models/massspring/quartet.h"

namespace hcosim::models::massspring {
namespace {

constexpr double kTiny = 1e-12;  // m: below this a spring has no direction

// 3x3 blocks of -df/dx (stiffness) and -df/dv (damping) of one spring.
void spring_blocks(const Lattice& l, const Spring& s, const Eigen::Matrix3Xd& x, Eigen::Matrix3d& k,
                   Eigen::Matrix3d& c) {
  double len;
  const Eigen::Vector3d u = spring_direction(l, s, x, &len);
  const Eigen::Matrix3d p = u * u.transpose();
  // A zero-rest-length spring's force k (x_j - x_i) is linear: K = k I at
  // any length, including zero where it has no direction.
  const double geometric = s.rest == 0 ? 1.0 : len > kTiny ? std::max(0.0, 1.0 - s.rest / len) : 0.0;
  k = s.k * (p + geometric * (Eigen::Matrix3d::Identity() - p));
  c = s.b * p;
}

}  // namespace

Eigen::Vector3d spring_direction(const Lattice& l, const Spring& s, const Eigen::Matrix3Xd& x, double* length) {
  const Eigen::Vector3d d = x.col(s.j) - x.col(s.i);
  *length = d.norm();
  if (*length > kTiny) return d / *length;
  const Eigen::Vector3d r = l.rest.col(s.j) - l.rest.col(s.i);
  const double rn = r.norm();
  return rn > kTiny ? Eigen::Vector3d(r / rn) : Eigen::Vector3d::Zero();
}

void add_forces(const Lattice& l, const std::vector<int>& springs, const std::vector<int>& quartets,
                const std::vector<int>& masses, const std::vector<PointForce>& loads, const Eigen::Matrix3Xd& x,
                const Eigen::Matrix3Xd& v, Eigen::Matrix3Xd& f) {
  double* F = f.data();
  for (const int si : springs) {
    const Spring& s = l.springs[si];
    const int a = 3 * s.i, b = 3 * s.j;
    double u[3];
    const double mag = spring_tension(l, s, x, v, u);
    for (int c = 0; c < 3; ++c) {
      F[a + c] += mag * u[c];
      F[b + c] -= mag * u[c];
    }
  }
  for (const int qi : quartets) {
    const Quartet& h = l.quartets[qi];
    Eigen::Vector3d fh[4];
    quartet_forces(h, x, v, fh);
    f.col(h.i) += fh[0], f.col(h.j) += fh[1], f.col(h.k) += fh[2], f.col(h.l) += fh[3];
  }
  for (const int i : masses) f.col(i) += l.mass[i] * l.gravity - l.drag * v.col(i);
  for (const PointForce& p : loads) f.col(p.mass) += p.force;
}

Energy energy(const Lattice& l, const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v) {
  Energy e;
  for (const Spring& s : l.springs) {
    const double stretch = (x.col(s.j) - x.col(s.i)).norm() - s.rest;
    e.elastic += 0.5 * s.k * stretch * stretch;
  }
  for (const Quartet& q : l.quartets) (q.measure == Measure::angle ? e.bending : e.volume) += quartet_energy(q, x);
  for (int i = 0; i < l.size(); ++i) {
    e.kinetic += 0.5 * l.mass[i] * v.col(i).squaredNorm();
    e.gravity -= l.mass[i] * l.gravity.dot(x.col(i) - l.rest.col(i));
  }
  return e;
}

Eigen::Vector3d momentum(const Lattice& l, const Eigen::Matrix3Xd& v) {
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (int i = 0; i < l.size(); ++i)
    if (!l.anchored[i]) p += l.mass[i] * v.col(i);
  return p;
}

void implicit_triplets(const Lattice& l, const std::vector<int>& springs, const std::vector<int>& quartets,
                       const std::vector<int>& masses, const std::vector<int>& slot, const Eigen::Matrix3Xd& x,
                       double h, std::vector<Eigen::Triplet<double>>& t) {
  t.clear();
  t.reserve(masses.size() * 3 + springs.size() * 36 + quartets.size() * 144);
  auto block = [&t](int a, int b, const Eigen::Matrix3d& m) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t.emplace_back(3 * a + r, 3 * b + c, m(r, c));
  };
  for (std::size_t a = 0; a < masses.size(); ++a)
    for (int r = 0; r < 3; ++r) t.emplace_back(3 * a + r, 3 * a + r, l.mass[masses[a]] + h * l.drag);
  Eigen::Matrix3d k, c;
  for (const int si : springs) {
    const Spring& s = l.springs[si];
    spring_blocks(l, s, x, k, c);
    const Eigen::Matrix3d m = h * c + h * h * k;
    const int a = slot[s.i], b = slot[s.j];
    if (a >= 0) block(a, a, m);
    if (b >= 0) block(b, b, m);
    if (a >= 0 && b >= 0) block(a, b, -m), block(b, a, -m);
  }
  for (const int qi : quartets) {
    const Quartet& e = l.quartets[qi];
    Eigen::Vector3d g[4];
    strain(e, x, g);
    const int corner[4] = {slot[e.i], slot[e.j], slot[e.k], slot[e.l]};
    const double w = h * e.b + h * h * e.stiffness;
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q)
        if (corner[p] >= 0 && corner[q] >= 0) block(corner[p], corner[q], w * g[p] * g[q].transpose());
  }
}

Eigen::SparseMatrix<double> implicit_matrix(const Lattice& l, const std::vector<int>& springs,
                                            const std::vector<int>& quartets, const std::vector<int>& masses,
                                            const std::vector<int>& slot, const Eigen::Matrix3Xd& x, double h) {
  std::vector<Eigen::Triplet<double>> t;
  implicit_triplets(l, springs, quartets, masses, slot, x, h, t);
  const int n = int(masses.size()) * 3;
  Eigen::SparseMatrix<double> a(n, n);
  a.setFromTriplets(t.begin(), t.end());
  return a;
}

void add_stiffness_times(const Lattice& l, const std::vector<int>& springs, const std::vector<int>& quartets,
                         const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& v, double scale, Eigen::Matrix3Xd& out) {
  Eigen::Matrix3d k, c;
  for (const int si : springs) {
    const Spring& s = l.springs[si];
    spring_blocks(l, s, x, k, c);
    const Eigen::Vector3d kv = scale * k * (v.col(s.i) - v.col(s.j));
    out.col(s.i) += kv;
    out.col(s.j) -= kv;
  }
  for (const int qi : quartets) {
    const Quartet& e = l.quartets[qi];
    Eigen::Vector3d g[4];
    strain(e, x, g);
    const int corner[4] = {e.i, e.j, e.k, e.l};
    double gv = 0;
    for (int q = 0; q < 4; ++q) gv += g[q].dot(v.col(corner[q]));
    for (int q = 0; q < 4; ++q) out.col(corner[q]) += scale * e.stiffness * gv * g[q];
  }
}

}  // namespace hcosim::models::massspring
