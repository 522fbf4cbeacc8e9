#include "models/fem/corotational.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

#include "models/massspring/quartet.h"

namespace hcosim::models::fem {

namespace {

using Mat12 = Eigen::Matrix<double, 12, 12>;
using Vec12 = Eigen::Matrix<double, 12, 1>;

void need_fem(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("fem: " + what);
}

// The rotation of the polar decomposition F = R S, S symmetric, with
// det R = +1: an inverted element's (det F < 0) flips along its smallest
// singular direction, so that its elastic force pushes it back through
// zero volume rather than holding it mirrored.
Eigen::Matrix3d rotation(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d U = svd.matrixU();
  const Eigen::Matrix3d V = svd.matrixV();
  if ((U * V.transpose()).determinant() < 0) U.col(2) *= -1;
  return U * V.transpose();
}

}  // namespace

Mesh box_mesh(int nx, int ny, int nz, double spacing) {
  need_fem(nx >= 2 && ny >= 2 && nz >= 2, "a box needs at least 2 nodes along each axis");
  need_fem(spacing > 0 && std::isfinite(spacing), "the spacing must be finite and > 0");
  Mesh m;
  m.rest.resize(3, nx * ny * nz);
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) m.rest.col(i + nx * (j + ny * k)) = spacing * Eigen::Vector3d(i, j, k);
  m.tets = models::massspring::box_tetrahedra(nx, ny, nz);
  m.anchored.assign(m.rest.cols(), 0);
  return m;
}

models::massspring::State rest_state(const Mesh& mesh) {
  models::massspring::State s;
  s.x = mesh.rest;
  s.v.setZero(3, mesh.size());
  s.quiet.assign(mesh.size(), 0);
  return s;
}

struct Corotational::Impl {
  struct Element {
    std::array<int, 4> c;
    Eigen::Matrix3d bm;          // Dm^-1, Dm the rest edge matrix
    Mat12 k;                     // N/m, the linear stiffness at rest
    std::array<int, 48> slot{};  // per corner pair (p, q) and column of the block: its first entry in A
  };

  Mesh mesh;
  Material mat;
  Options opt;
  Eigen::VectorXd mass;
  std::vector<Element> elements;
  std::vector<std::vector<int>> incident;  // per node, its elements
  std::vector<std::uint8_t> held;
  std::vector<int> diagonal;  // per dof, its diagonal entry in A

  Eigen::SparseMatrix<double> A;  // the step's matrix, pattern fixed
  Eigen::ConjugateGradient<Eigen::SparseMatrix<double>, Eigen::Lower | Eigen::Upper> cg;
  Eigen::VectorXd rhs, guess, fixed;

  Impl(Mesh m, const Material& material, const Options& options) : mesh(std::move(m)), mat(material), opt(options) {
    const int n = mesh.size();
    need_fem(mat.young > 0 && std::isfinite(mat.young), "Young's modulus must be finite and > 0");
    need_fem(mat.poisson > -1 && mat.poisson < 0.5, "Poisson's ratio must be in (-1, 0.5)");
    need_fem(mat.density > 0 && std::isfinite(mat.density), "the density must be finite and > 0");
    need_fem(mat.alpha >= 0 && mat.beta >= 0 && std::isfinite(mat.alpha + mat.beta),
             "Rayleigh damping must be finite and >= 0");
    need_fem(opt.dt > 0 && std::isfinite(opt.dt), "dt must be finite and > 0");
    need_fem(opt.tolerance > 0 && opt.tolerance < 1, "the tolerance must be in (0, 1)");
    need_fem(mesh.rest.allFinite(), "rest positions must be finite");
    need_fem(int(mesh.anchored.size()) == n,
             "anchored has " + std::to_string(mesh.anchored.size()) + " flags for " + std::to_string(n) + " nodes");
    need_fem(!mesh.tets.empty(), "the mesh has no tetrahedra");
    need_fem(mesh.scale.empty() || mesh.scale.size() == mesh.tets.size(),
             "scale has " + std::to_string(mesh.scale.size()) + " entries for " + std::to_string(mesh.tets.size()) +
                 " tetrahedra");
    const double lambda = mat.young * mat.poisson / ((1 + mat.poisson) * (1 - 2 * mat.poisson));
    const double mu = mat.young / (2 * (1 + mat.poisson));
    mass.setZero(n);
    incident.resize(n);
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      Element e;
      e.c = mesh.tets[t];
      const std::string name = "tetrahedron " + std::to_string(t);
      for (int p = 0; p < 4; ++p) {
        need_fem(e.c[p] >= 0 && e.c[p] < n, name + " has a corner outside 0.." + std::to_string(n - 1));
        for (int q = 0; q < p; ++q) need_fem(e.c[p] != e.c[q], name + " repeats corner " + std::to_string(e.c[p]));
      }
      Eigen::Matrix3d dm;
      for (int a = 0; a < 3; ++a) dm.col(a) = mesh.rest.col(e.c[a + 1]) - mesh.rest.col(e.c[0]);
      if (dm.determinant() < 0) std::swap(e.c[2], e.c[3]), dm.col(1).swap(dm.col(2));
      const double volume = dm.determinant() / 6;
      need_fem(volume > 1e-18 * std::pow(dm.colwise().norm().maxCoeff(), 3), name + " has no volume at rest");
      const double scale = mesh.scale.empty() ? 1.0 : mesh.scale[t];
      need_fem(scale > 0 && std::isfinite(scale), name + " has a scale that is not finite and > 0");
      e.bm = dm.inverse();
      // Shape function gradients: rows of Dm^-1 for corners 1..3, corner 0 minus their sum.
      Eigen::Matrix<double, 3, 4> g;
      for (int a = 0; a < 3; ++a) g.col(a + 1) = e.bm.row(a).transpose();
      g.col(0) = -(g.col(1) + g.col(2) + g.col(3));
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
          e.k.block<3, 3>(3 * p, 3 * q) =
              scale * volume *
              (lambda * g.col(p) * g.col(q).transpose() + mu * g.col(q) * g.col(p).transpose() +
               mu * g.col(p).dot(g.col(q)) * Eigen::Matrix3d::Identity());
      for (int p = 0; p < 4; ++p) mass[e.c[p]] += mat.density * volume / 4, incident[e.c[p]].push_back(int(t));
      elements.push_back(e);
    }
    for (int i = 0; i < n; ++i)
      need_fem(mass[i] > 0 || mesh.anchored[i], "node " + std::to_string(i) + " is in no tetrahedron and not anchored");
    held.assign(n, 0);
    build_pattern();
  }

  // A's pattern (every pair of nodes that share an element, 3 x 3 blocks)
  // and where each element's blocks and each dof's diagonal lie in it.
  void build_pattern() {
    const int n = mesh.size();
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(elements.size() * 144 + 3 * n);
    for (const Element& e : elements)
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
          for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) t.emplace_back(3 * e.c[p] + r, 3 * e.c[q] + c, 0.0);
    for (int d = 0; d < 3 * n; ++d) t.emplace_back(d, d, 0.0);
    A.resize(3 * n, 3 * n);
    A.setFromTriplets(t.begin(), t.end());
    A.makeCompressed();
    auto entry = [&](int row, int col) {
      const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[col];
      const int* end = A.innerIndexPtr() + A.outerIndexPtr()[col + 1];
      return int(std::lower_bound(begin, end, row) - A.innerIndexPtr());
    };
    for (Element& e : elements)
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q)
          for (int c = 0; c < 3; ++c) e.slot[12 * p + 3 * q + c] = entry(3 * e.c[p], 3 * e.c[q] + c);
    diagonal.resize(3 * n);
    for (int d = 0; d < 3 * n; ++d) diagonal[d] = entry(d, d);
  }

  bool fixed_node(int i) const { return mesh.anchored[i] || held[i]; }

  // The element's corner positions as one vector, rotated back into its
  // rest frame, minus its rest positions: the displacement K acts on.
  Vec12 local_displacement(const Element& e, const Eigen::Matrix3d& R, const Eigen::Matrix3Xd& x) const {
    Vec12 u;
    for (int p = 0; p < 4; ++p) u.segment<3>(3 * p) = R.transpose() * x.col(e.c[p]) - mesh.rest.col(e.c[p]);
    return u;
  }

  Eigen::Matrix3d element_rotation(const Element& e, const Eigen::Matrix3Xd& x) const {
    Eigen::Matrix3d ds;
    for (int a = 0; a < 3; ++a) ds.col(a) = x.col(e.c[a + 1]) - x.col(e.c[0]);
    return rotation(ds * e.bm);
  }

  // The element's elastic force on its corners at x, with rotation R.
  Vec12 element_force(const Element& e, const Eigen::Matrix3d& R, const Eigen::Matrix3Xd& x) const {
    const Vec12 f = -(e.k * local_displacement(e, R, x));
    Vec12 out;
    for (int p = 0; p < 4; ++p) out.segment<3>(3 * p) = R * f.segment<3>(3 * p);
    return out;
  }

  StepInfo step(models::massspring::State& s, const std::vector<models::massspring::PointForce>& loads) {
    const int n = mesh.size();
    const double h = opt.dt;
    // Forces at the step's start, and the matrix cm M + ck K: for implicit
    // Euler (M + h D + h^2 K) v1 = M v0 + h f, for the trapezoidal rule
    // (M + h/2 D + h^2/4 K) v1 = M v0 + h f - h/2 D v0 - h^2/4 K v0,
    // D = alpha M + beta K.
    const bool trapezoid = opt.scheme == Scheme::trapezoidal;
    const double cm = 1 + (trapezoid ? 0.5 : 1) * h * mat.alpha;
    const double ks = trapezoid ? 0.5 * h * mat.beta + 0.25 * h * h : h * mat.beta + h * h;
    Eigen::Matrix3Xd f = Eigen::Matrix3Xd::Zero(3, n);
    for (const models::massspring::PointForce& p : loads) f.col(p.mass) += p.force;
    std::fill(A.valuePtr(), A.valuePtr() + A.nonZeros(), 0.0);
    double* values = A.valuePtr();
    for (const Element& e : elements) {
      const Eigen::Matrix3d R = element_rotation(e, s.x);
      const Vec12 fe = element_force(e, R, s.x);
      for (int p = 0; p < 4; ++p) f.col(e.c[p]) += fe.segment<3>(3 * p);
      for (int p = 0; p < 4; ++p)
        for (int q = 0; q < 4; ++q) {
          const Eigen::Matrix3d b = ks * R * e.k.block<3, 3>(3 * p, 3 * q) * R.transpose();
          for (int c = 0; c < 3; ++c) {
            double* col = values + e.slot[12 * p + 3 * q + c];
            col[0] += b(0, c), col[1] += b(1, c), col[2] += b(2, c);
          }
        }
    }
    for (int i = 0; i < n; ++i)
      for (int r = 0; r < 3; ++r) values[diagonal[3 * i + r]] += cm * mass[i];
    // The right-hand side; the fixed nodes' velocities are known. The
    // trapezoidal rule's (1 - h alpha / 2) M v0 - (h beta / 2 + h^2 / 4) K v0
    // is 2 M v0 - A v0.
    const Eigen::Map<const Eigen::VectorXd> v0(s.v.data(), 3 * n);
    if (trapezoid)
      rhs = -(A * v0);
    else
      rhs.setZero(3 * n);
    fixed.setZero(3 * n);
    for (int i = 0; i < n; ++i) {
      rhs.segment<3>(3 * i) += (trapezoid ? 2 : 1) * mass[i] * s.v.col(i) + h * f.col(i);
      if (held[i]) fixed.segment<3>(3 * i) = s.v.col(i);
    }
    if (!fixed.isZero()) rhs -= A * fixed;
    for (int col = 0; col < 3 * n; ++col)
      for (int k = A.outerIndexPtr()[col]; k < A.outerIndexPtr()[col + 1]; ++k) {
        const int row = A.innerIndexPtr()[k];
        if (fixed_node(row / 3) || fixed_node(col / 3)) values[k] = row == col ? 1.0 : 0.0;
      }
    for (int i = 0; i < n; ++i)
      if (fixed_node(i)) rhs.segment<3>(3 * i) = fixed.segment<3>(3 * i);
    guess = Eigen::Map<const Eigen::VectorXd>(s.v.data(), 3 * n);
    for (int i = 0; i < n; ++i)
      if (fixed_node(i)) guess.segment<3>(3 * i) = fixed.segment<3>(3 * i);
    cg.setTolerance(opt.tolerance);
    cg.setMaxIterations(std::max(100, 3 * n));
    cg.compute(A);
    Eigen::VectorXd v1 = cg.solveWithGuess(rhs, guess);
    StepInfo info;
    info.iterations = int(cg.iterations());
    // CG stalls where A is ill-conditioned (quasi-static steps of a long
    // beam) or its residual underflows (a body come to rest): a direct
    // factorization then, rather than an inexact step.
    if (cg.info() != Eigen::Success) {
      const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
      if (ldlt.info() != Eigen::Success)
        throw std::runtime_error("fem: the step's matrix is singular (t = " + std::to_string(s.t) +
                                 " s); the state is left as before the step");
      v1 = ldlt.solve(rhs);
      info.direct = true;
    }
    if (!v1.allFinite())
      throw std::runtime_error("fem: the step's velocities are not finite (t = " + std::to_string(s.t) +
                               " s); the state is left as before the step");
    for (int i = 0; i < n; ++i) {
      if (mesh.anchored[i]) {
        s.x.col(i) = mesh.rest.col(i), s.v.col(i).setZero();
      } else if (!held[i]) {
        const Eigen::Vector3d v = v1.segment<3>(3 * i);
        const Eigen::Vector3d dx = trapezoid ? Eigen::Vector3d(0.5 * h * (s.v.col(i) + v)) : Eigen::Vector3d(h * v);
        s.x.col(i) += dx;
        s.v.col(i) = v;
      }
    }
    s.t += h;
    return info;
  }
};

Corotational::Corotational(Mesh mesh, const Material& material, const Options& options)
    : impl_(std::make_unique<Impl>(std::move(mesh), material, options)) {}

Corotational::~Corotational() = default;

void check_step(int n, const models::massspring::State& s, const std::vector<models::massspring::PointForce>& loads) {
  need_fem(s.x.cols() == n && s.v.cols() == n,
           "the state has " + std::to_string(s.x.cols()) + " nodes, the mesh " + std::to_string(n));
  need_fem(s.x.allFinite() && s.v.allFinite(), "the state must be finite");
  for (const models::massspring::PointForce& p : loads) {
    need_fem(p.mass >= 0 && p.mass < n,
             "a load on node " + std::to_string(p.mass) + ", the mesh has " + std::to_string(n));
    need_fem(p.force.allFinite(), "a non-finite load on node " + std::to_string(p.mass));
  }
}

StepInfo Corotational::step(models::massspring::State& s, const std::vector<models::massspring::PointForce>& loads) {
  check_step(impl_->mesh.size(), s, loads);
  return impl_->step(s, loads);
}

void Corotational::hold(int node, bool held) {
  need_fem(node >= 0 && node < impl_->mesh.size(), "cannot hold node " + std::to_string(node));
  need_fem(!impl_->mesh.anchored[node], "node " + std::to_string(node) + " is anchored, not free to hold");
  impl_->held[node] = held;
}

Eigen::Vector3d Corotational::force_on(int node, const models::massspring::State& s) const {
  const Impl& m = *impl_;
  need_fem(node >= 0 && node < m.mesh.size() && s.x.cols() == m.mesh.size(),
           "force_on: no node " + std::to_string(node));
  Eigen::Vector3d f = Eigen::Vector3d::Zero();
  for (const int k : m.incident[node]) {
    const Impl::Element& e = m.elements[k];
    const Vec12 fe = m.element_force(e, m.element_rotation(e, s.x), s.x);
    for (int p = 0; p < 4; ++p)
      if (e.c[p] == node) f += fe.segment<3>(3 * p);
  }
  return f;
}

double Corotational::energy(const Eigen::Matrix3Xd& x) const {
  const Impl& m = *impl_;
  need_fem(x.cols() == m.mesh.size(), "energy: positions of the wrong size");
  double sum = 0;
  for (const Impl::Element& e : m.elements) {
    const Vec12 u = m.local_displacement(e, m.element_rotation(e, x), x);
    sum += 0.5 * u.dot(e.k * u);
  }
  return sum;
}

Eigen::SparseMatrix<double> Corotational::rest_stiffness() const {
  const Impl& m = *impl_;
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(m.elements.size() * 144);
  for (const Impl::Element& e : m.elements)
    for (int p = 0; p < 4; ++p)
      for (int q = 0; q < 4; ++q)
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) t.emplace_back(3 * e.c[p] + r, 3 * e.c[q] + c, e.k(3 * p + r, 3 * q + c));
  Eigen::SparseMatrix<double> k(3 * m.mesh.size(), 3 * m.mesh.size());
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

const Mesh& Corotational::mesh() const { return impl_->mesh; }
const Eigen::VectorXd& Corotational::mass() const { return impl_->mass; }
const Material& Corotational::material() const { return impl_->mat; }
const Options& Corotational::options() const { return impl_->opt; }

}  // namespace hcosim::models::fem
