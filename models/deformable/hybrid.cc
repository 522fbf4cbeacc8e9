#include "models/deformable/hybrid.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <mutex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include <Eigen/SparseCholesky>

#include "models/deformable/surface.h"
#include "models/massspring/quartet.h"

namespace hcosim::models::deformable {

namespace {

void need_hybrid(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("hybrid: " + what);
}

// The +x half past the body's centre (rest, world).
bool stiff_side(const HybridSpec& s, const Eigen::Vector3d& rest) {
  return s.stiff_ratio != 1 && rest.x() > s.centre.x() + 1e-9 * s.size;
}

// The shape scaled and moved into place, welded.
models::massspring::TriangleMesh placed(const HybridSpec& s) {
  models::massspring::TriangleMesh m = s.shape;
  need_hybrid(m.vertices.cols() >= 4 && m.vertices.allFinite(), "a shape needs at least 4 finite vertices");
  for (const Eigen::Vector3i& t : m.triangles)
    need_hybrid(t.minCoeff() >= 0 && t.maxCoeff() < m.vertices.cols(), "a shape's triangle indexes no vertex");
  const Eigen::Vector3d lo = m.vertices.rowwise().minCoeff(), hi = m.vertices.rowwise().maxCoeff();
  const double longest = (hi - lo).maxCoeff();
  need_hybrid(longest > 0, "a shape needs an extent");
  m.vertices = ((m.vertices.colwise() - 0.5 * (lo + hi)) * (s.size / longest)).colwise() + s.centre;
  models::massspring::weld(m, 1e-9 * s.size);
  try {
    models::massspring::check_closed(m);
  } catch (const std::invalid_argument& e) {
    need_hybrid(false, std::string("shape: ") + e.what());
  }
  return m;
}

}  // namespace

const char* name(VisualMap m) {
  switch (m) {
    case VisualMap::mvc:
      return "mvc";
    case VisualMap::mvc_sparse:
      return "mvc_sparse";
    case VisualMap::trilinear:
      return "trilinear";
  }
  return "?";
}

VisualMap parse_visual_map(const std::string& s) {
  for (VisualMap m : {VisualMap::mvc, VisualMap::mvc_sparse, VisualMap::trilinear})
    if (s == name(m)) return m;
  throw std::invalid_argument("unknown visual map '" + s + "': one of mvc, mvc_sparse, trilinear");
}

const char* name(BehaviorModel m) {
  switch (m) {
    case BehaviorModel::springs:
      return "springs";
    case BehaviorModel::fem:
      return "fem";
    case BehaviorModel::modal:
      return "modal";
  }
  return "?";
}

BehaviorModel parse_behavior_model(const std::string& s) {
  for (BehaviorModel m : {BehaviorModel::springs, BehaviorModel::fem, BehaviorModel::modal})
    if (s == name(m)) return m;
  throw std::invalid_argument("unknown behavior model '" + s + "': one of springs, fem, modal");
}

void check(const HybridSpec& s) {
  need_hybrid(s.elements >= 3 && s.elements <= 100, "elements must be in [3, 100] per edge");
  need_hybrid(s.size > 0 && std::isfinite(s.size), "size must be finite and > 0");
  need_hybrid(s.centre.allFinite(), "centre must be finite");
  need_hybrid(s.stiff_ratio >= 1 && s.stiff_ratio <= 100, "stiff_ratio must be in [1, 100]");
  need_hybrid(s.volume >= 0 && s.volume <= 1000, "volume must be in [0, 1000]");
  need_hybrid(s.volume_floor > 0 && s.volume_floor <= 1, "volume_floor must be in (0, 1]");
  need_hybrid(s.modes >= 1 && s.modes <= models::fem::Modal::kMaxDofs,
              "modes must be in [1, " + std::to_string(models::fem::Modal::kMaxDofs) + "]");
  need_hybrid(s.visual_subdivisions >= 1 && s.visual_subdivisions <= 1000, "visual_subdivisions must be in [1, 1000]");
  need_hybrid(s.keep > 0 && s.keep <= 1, "keep must be in (0, 1]");
  need_hybrid(s.visual_tolerance >= 0 && s.visual_tolerance < s.size, "visual_tolerance must be in [0, size)");
  need_hybrid(s.tip_radius >= 0 && s.tip_radius < 0.5 * s.size, "tip_radius must be in [0, size / 2)");
  need_hybrid(s.shape.triangles.empty() || s.map != VisualMap::trilinear, "a shape is mapped by mvc or mvc_sparse");
}

Eigen::AlignedBox3d rest_box(const HybridSpec& s) {
  check(s);
  if (s.shape.triangles.empty())
    return {s.centre - Eigen::Vector3d::Constant(0.5 * s.size), s.centre + Eigen::Vector3d::Constant(0.5 * s.size)};
  const models::massspring::TriangleMesh m = placed(s);
  return {m.vertices.rowwise().minCoeff(), m.vertices.rowwise().maxCoeff()};
}

models::massspring::TriangleMesh hybrid_visual(const HybridSpec& s) {
  check(s);
  if (!s.shape.triangles.empty()) return placed(s);
  const Eigen::AlignedBox3d box = rest_box(s);
  return rounded_box(s.visual_subdivisions, box.min(), box.max(), s.visual_exponent);
}

models::massspring::Voxels hybrid_voxels(const HybridSpec& s) {
  check(s);
  const double spacing = s.size / (s.elements - 1);
  if (!s.shape.triangles.empty()) return models::massspring::voxelise(placed(s), spacing);
  const int n = s.elements - 1;
  models::massspring::Voxels v = models::massspring::box_voxels(n, n, n, spacing);
  v.origin = rest_box(s).min();
  return v;
}

ChainLattice hybrid_chains(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  const std::vector<int> mass = v.masses();
  const Eigen::Array3i n = v.nodes();
  ChainLattice l = make_chain_box(n.x(), n.y(), n.z(), v.spacing, s.chain);
  l.origin = v.origin;
  ChainMaterial hard = s.chain;
  hard.stiffness *= s.stiff_ratio;
  for (double* r : {&hard.stretch, &hard.compress, &hard.shear}) *r /= s.stiff_ratio;
  for (int e = 0; e < l.size(); ++e) {
    l.present[e] = mass[e] >= 0;
    if (stiff_side(s, l.rest(e))) l.material[e] = hard;
    l.anchored[e] = l.present[e] && e < n.x() * n.y();  // the bottom layer, k = 0
  }
  return l;
}

namespace {

// Anchors the masses on the bottom layer of nodes.
void anchor_bottom(const models::massspring::Voxels& v, std::vector<std::uint8_t>& anchored,
                   const Eigen::Matrix3Xd& rest) {
  int count = 0;
  for (int i = 0; i < rest.cols(); ++i) count += anchored[i] = rest(2, i) < v.origin.z() + 0.5 * v.spacing;
  need_hybrid(count >= 3, "the body's lowest layer of nodes holds " + std::to_string(count) +
                              " (3 or more needed): a shape must rest on a flat underside");
}

}  // namespace

models::massspring::Lattice hybrid_masses(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  models::massspring::Lattice l = models::massspring::make_from_voxels(v, s.material);
  for (models::massspring::Spring& sp : l.springs)
    if (stiff_side(s, l.rest.col(sp.i)) && stiff_side(s, l.rest.col(sp.j))) sp.k *= s.stiff_ratio;
  if (s.volume > 0) {
    const double modulus = s.volume * s.material.k / v.spacing;
    const std::size_t first = l.quartets.size();
    models::massspring::add_volumes(l, models::massspring::voxel_tetrahedra(v), modulus, 0, s.volume_floor);
    for (std::size_t q = first; q < l.quartets.size(); ++q) {
      models::massspring::Quartet& t = l.quartets[q];
      if (stiff_side(s, l.rest.col(t.i)) && stiff_side(s, l.rest.col(t.j)) && stiff_side(s, l.rest.col(t.k)) &&
          stiff_side(s, l.rest.col(t.l)))
        t.stiffness *= s.stiff_ratio;
    }
  }
  anchor_bottom(v, l.anchored, l.rest);
  return l;
}

models::fem::Mesh hybrid_mesh(const HybridSpec& s) {
  const models::massspring::Voxels v = hybrid_voxels(s);
  models::fem::Mesh m;
  m.rest = models::massspring::make_from_voxels(v, s.material).rest;
  m.tets = models::massspring::voxel_tetrahedra(v);
  m.anchored.assign(m.size(), 0);
  m.scale.assign(m.tets.size(), 1);
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    bool stiff = true;
    for (const int c : m.tets[t]) stiff = stiff && stiff_side(s, m.rest.col(c));
    if (stiff) m.scale[t] = s.stiff_ratio;
  }
  anchor_bottom(v, m.anchored, m.rest);
  return m;
}

namespace {

// The behavior model of a spec stepped towards rest: implicit Euler at 1
// s steps, each close to a Newton step (CG to `tolerance`); the springs,
// or for the FEM and the modal model, the corotational FEM.
struct Settling {
  Settling(const HybridSpec& spec, double tolerance) {
    if (spec.behavior_model != BehaviorModel::springs) {
      models::fem::Options o;
      o.dt = 1, o.tolerance = tolerance;
      fem = std::make_unique<models::fem::Corotational>(hybrid_mesh(spec), spec.fem, o);
      state = models::fem::rest_state(fem->mesh());
    } else {
      models::massspring::Options o;
      o.integrator = models::massspring::Integrator::implicit_euler;
      o.dt = 1, o.tolerance = tolerance;
      springs = std::make_unique<models::massspring::Simulator>(hybrid_masses(spec), o);
      state = models::massspring::rest_state(springs->lattice());
    }
  }
  const Eigen::Matrix3Xd& rest() const { return fem ? fem->mesh().rest : springs->lattice().rest; }
  void step(const std::vector<models::massspring::PointForce>& loads) {
    fem ? void(fem->step(state, loads)) : void(springs->step(state, loads));
  }
  std::unique_ptr<models::massspring::Simulator> springs;
  std::unique_ptr<models::fem::Corotational> fem;
  models::massspring::State state;
};

// The behavior model of a spec with one mass held where it is put and the
// rest settled to rest around it. The modal model's is its kept modes'
// stiffness at the mass, in one step.
class Held {
 public:
  Held(const HybridSpec& spec, int mass, double tolerance) : mass_(mass), model_(spec, tolerance) {
    need_hybrid(mass >= 0 && mass < model_.state.x.cols(), "no mass " + std::to_string(mass));
    if (spec.behavior_model == BehaviorModel::modal) {
      stiffness_ = models::fem::Modal(*model_.fem, models::fem::ModalOptions{spec.behavior.dt, spec.modes})
                       .compliance(mass)
                       .inverse();
      modal_ = true;
    }
    model_.fem ? model_.fem->hold(mass, true) : model_.springs->hold(mass, true);
  }
  const Eigen::Matrix3Xd& rest() const { return model_.rest(); }
  // Puts the held mass at x and settles the rest until the holder's force
  // changes by under `change` of itself; returns that force (N).
  Eigen::Vector3d settle(const Eigen::Vector3d& x, double change) {
    if (modal_) return -stiffness_ * (x - rest().col(mass_));
    model_.state.x.col(mass_) = x;
    Eigen::Vector3d last = Eigen::Vector3d::Constant(1e300);
    for (int k = 0; k < 1000; ++k) {
      model_.step({});
      const Eigen::Vector3d f = force();
      if ((f - last).norm() <= change * f.norm()) break;
      last = f;
    }
    return force();
  }

 private:
  Eigen::Vector3d force() const {
    return model_.fem ? model_.fem->force_on(mass_, model_.state) : model_.springs->spring_force(mass_, model_.state);
  }
  int mass_;
  Settling model_;
  bool modal_ = false;
  Eigen::Matrix3d stiffness_;  // N/m, the modal model's at the mass
};

}  // namespace

Eigen::Vector3d behavior_static_force(const HybridSpec& spec, int mass, const Eigen::Vector3d& displacement) {
  need_hybrid(displacement.allFinite(), "the displacement must be finite");
  Held held(spec, mass, 1e-8);
  return held.settle(held.rest().col(mass) + displacement, 1e-9);
}

std::vector<double> gain_inputs(const HybridSpec& s) {
  std::vector<double> in{double(kForceGainVersion), double(s.elements), s.size, s.chain.stiffness, s.chain.stretch,
                         s.chain.compress, s.chain.shear, s.relax_rate, s.limit_stiffness, s.material.mass,
                         s.material.k, s.material.b, s.material.drag, s.volume, s.volume_floor, s.stiff_ratio,
                         double(s.behavior_model), s.fem.young, s.fem.poisson, s.fem.density, s.fem.alpha, s.fem.beta,
                         double(s.modes),
                         // The surface pressed and its map row (a shape's own mesh is below).
                         double(s.visual_subdivisions), s.visual_exponent, double(s.map), s.keep};
  for (int v = 0; v < s.shape.vertices.cols(); ++v)
    for (int c = 0; c < 3; ++c) in.push_back(s.shape.vertices(c, v));
  for (const Eigen::Vector3i& t : s.shape.triangles)
    for (int c = 0; c < 3; ++c) in.push_back(t[c]);
  return in;
}

namespace {

// y at x in a table of increasing xs and positive ys: the power law
// through the two samples beside it (a straight line on log scales, as
// the forces of a press grow), proportional to x below the first; y =
// 0 where a sample is not positive.
double power_between(const std::vector<double>& xs, const double* ys, double x) {
  if (x <= xs.front()) return ys[0] * x / xs.front();
  const std::size_t n = xs.size();
  const std::size_t k =
      std::min<std::size_t>(std::size_t(std::upper_bound(xs.begin(), xs.end(), x) - xs.begin()), n - 1);
  if (!(ys[k - 1] > 0 && ys[k] > 0)) return 0;
  return ys[k - 1] * std::pow(ys[k] / ys[k - 1], std::log(x / xs[k - 1]) / std::log(xs[k] / xs[k - 1]));
}

}  // namespace

double ForceGain::at(double d, bool stiff_side) const {
  return power_between(depth, (stiff_side && !stiff.empty() ? stiff : soft).data(), d);
}

namespace {

// The chain element (a grid node) a side's felt force is calibrated at:
// the top element in the middle of that side's half (of the whole top
// when both sides are one), the highest node of column (i, n.y / 2) or of
// the nearest column that has one.
int gain_element(const HybridSpec& spec, const models::massspring::Voxels& voxels, bool stiff) {
  const std::vector<int> mass = voxels.masses();
  const Eigen::Array3i n = voxels.nodes();
  const int i = spec.stiff_ratio == 1 ? n.x() / 2 : stiff ? n.x() - 1 - n.x() / 4 : n.x() / 4;
  int e = -1;
  for (int k = n.z() - 1; k >= 0; --k)
    for (int j = 0; j < n.y(); ++j)
      for (int c = 0; c < n.x(); ++c) {
        const int node = int(voxels.node(c, j, k));
        if (mass[node] < 0) continue;
        const auto off = [&](int m) {
          const int di = m % n.x() - i, dj = m / n.x() % n.y() - n.y() / 2;
          return di * di + dj * dj;
        };
        if (e < 0 || off(node) < off(e)) e = node;
      }
  return e;
}

// A side's gain point, and the chain element touch() takes there: the
// middle of a top cell face beside the side's gain element (half a cell
// along +x and +y from its node), where a press spreads over four masses,
// not onto one (under which the lattice stiffens fastest with depth).
std::pair<Eigen::Vector3d, int> find_gain_point(const HybridSpec& spec, const models::massspring::Voxels& voxels,
                                                const SChain& chains, bool stiff) {
  const Eigen::Vector3d p =
      chains.lattice().rest(gain_element(spec, voxels, stiff)) + 0.5 * voxels.spacing * Eigen::Vector3d(1, 1, 0);
  return {p, chains.nearest_surface(p)};
}

// The visual vertex nearest a point (rest, world).
int nearest_vertex(const Eigen::Matrix3Xd& vertices, const Eigen::Vector3d& p) {
  int v = 0;
  (vertices.colwise() - p).colwise().squaredNorm().minCoeff(&v);
  return v;
}

// The visual map's cage: the masses it reads, where their rest is drawn
// for its weights, and its triangles (empty for the trilinear map, whose
// cage is every mass where it is).
struct Cage {
  std::vector<int> masses;
  Eigen::Matrix3Xd rest;
  std::vector<Eigen::Vector3i> triangles;
};

Cage map_cage(const HybridSpec& spec, const models::massspring::Voxels& voxels, const models::massspring::Lattice& lat,
              const models::massspring::TriangleMesh& visual) {
  Cage c;
  if (spec.map == VisualMap::trilinear) {
    for (int i = 0; i < lat.size(); ++i) c.masses.push_back(i);
    return c;
  }
  const GridSurface g = voxel_surface(voxels);
  c.masses = g.nodes, c.triangles = g.triangles;
  c.rest.resize(3, c.masses.size());
  for (std::size_t v = 0; v < c.masses.size(); ++v) c.rest.col(v) = lat.rest.col(c.masses[v]);
  if (!spec.shape.triangles.empty()) {
    // A shape's surface lies up to a cell from the cells' boundary, where
    // mean value weights spread a point over much of the cage: the map's
    // cage is moved toward the surface, each node by at most 0.45 of a
    // cell so that no two meet. The map then reads the masses'
    // displacements, which are the same wherever their rest is drawn.
    const MeshProxy shape(visual.triangles, int(visual.vertices.cols()));
    for (int v = 0; v < c.rest.cols(); ++v) {
      const Eigen::Vector3d to =
          shape.point(visual.vertices, shape.closest(visual.vertices, c.rest.col(v))) - c.rest.col(v);
      c.rest.col(v) += to * std::min(1.0, 0.45 * voxels.spacing / std::max(to.norm(), 1e-300));
    }
  }
  return c;
}

// The map's rows for `points` (visual rest points, 3 x m): what
// Hybrid's map holds for them.
Weights map_rows(const HybridSpec& spec, const models::massspring::Voxels& voxels, const Cage& cage,
                 const Eigen::Matrix3Xd& points) {
  if (spec.map == VisualMap::trilinear) {
    const Eigen::Array3i n = voxels.nodes();
    return trilinear_weights(n.x(), n.y(), n.z(), voxels.spacing, voxels.origin, points);
  }
  return mvc_map(spec, cage.rest, cage.triangles, points);
}

// N/m: the behavior model's stiffness at rest over its free masses (mass
// i's x, y, z at 3 dof[i] + 0, 1, 2; dof -1: anchored). The springs' is
// their axial stiffness (at rest they carry no tension, and no volume
// floor is engaged); the FEM's and the modal model's is the FEM's.
Eigen::SparseMatrix<double> rest_stiffness(const HybridSpec& spec, const models::massspring::Lattice& lat,
                                           const std::vector<int>& dof, int free) {
  std::vector<Eigen::Triplet<double>> t;
  auto add = [&](int i, int j, int r, int c, double v) {
    if (dof[i] >= 0 && dof[j] >= 0) t.emplace_back(3 * dof[i] + r, 3 * dof[j] + c, v);
  };
  if (spec.behavior_model != BehaviorModel::springs) {
    const Eigen::SparseMatrix<double> k =
        models::fem::Corotational(hybrid_mesh(spec), spec.fem, models::fem::Options{}).rest_stiffness();
    for (int c = 0; c < k.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(k, c); it; ++it)
        add(int(it.row() / 3), int(it.col() / 3), int(it.row() % 3), int(it.col() % 3), it.value());
  } else {
    for (const models::massspring::Spring& sp : lat.springs) {
      const Eigen::Vector3d d = lat.rest.col(sp.j) - lat.rest.col(sp.i);
      if (d.norm() <= 0) continue;
      const Eigen::Matrix3d b = sp.k * d.normalized() * d.normalized().transpose();
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          add(sp.i, sp.i, r, c, b(r, c)), add(sp.j, sp.j, r, c, b(r, c)), add(sp.i, sp.j, r, c, -b(r, c)),
              add(sp.j, sp.i, r, c, -b(r, c));
    }
  }
  Eigen::SparseMatrix<double> k(3 * free, 3 * free);
  k.setFromTriplets(t.begin(), t.end());
  return k;
}

// m/N, by row of `rows` (points x cage): how far each point of the drawn
// surface sinks along -normals.col(row) under 1 N pressing it, spread
// over the cage's masses by its row as touch() spreads the force, at
// rest. With K = P' L D L' P, a push p's compliance p' K^-1 p is
// |D^-1/2 L^-1 P p|^2: one factorisation, then a forward substitution a
// point that visits only the columns its few nonzeros reach.
std::vector<double> rest_compliance(const HybridSpec& spec, const models::massspring::Lattice& lat, const Weights& rows,
                                    const std::vector<int>& cage, const Eigen::Matrix3Xd& normals) {
  std::vector<int> dof(lat.size(), -1);
  int free = 0;
  for (int i = 0; i < lat.size(); ++i)
    if (!lat.anchored[i]) dof[i] = free++;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(rest_stiffness(spec, lat, dof, free));
  need_hybrid(ldlt.info() == Eigen::Success,
              "the behavior model's stiffness at rest is singular: a mass holds by nothing");
  const Eigen::SparseMatrix<double>& l = ldlt.matrixL().nestedExpression();
  const Eigen::VectorXi& to = ldlt.permutationP().indices();
  const Eigen::VectorXd& d = ldlt.vectorD();
  std::vector<double> c(rows.rows(), 0);
  Eigen::VectorXd y = Eigen::VectorXd::Zero(3 * free);
  for (int v = 0; v < rows.rows(); ++v) {
    int first = 3 * free;
    for (Weights::InnerIterator w(rows, v); w; ++w)
      if (const int m = dof[cage[w.col()]]; m >= 0)
        for (int k = 0; k < 3; ++k) {
          y[to[3 * m + k]] += w.value() * normals(k, v);
          first = std::min(first, int(to[3 * m + k]));
        }
    for (int j = first; j < 3 * free; ++j) {
      if (y[j] == 0) continue;
      for (Eigen::SparseMatrix<double>::InnerIterator e(l, j); e; ++e)
        if (e.row() > j) y[e.row()] -= e.value() * y[j];
      c[v] += y[j] * y[j] / d[j];
      y[j] = 0;
    }
  }
  return c;
}

// The same in the modal model's kept modes: its static answer to a load
// is the sum over them of the load's modal force times the shape over the
// frequency squared.
std::vector<double> modal_compliance(const models::fem::Modal& modal, const Weights& rows, const std::vector<int>& cage,
                                     const Eigen::Matrix3Xd& normals) {
  std::vector<Eigen::Matrix3Xd> shapes;
  for (int k = 0; k < modal.modes(); ++k) shapes.push_back(modal.shape(k));
  std::vector<double> c(rows.rows(), 0);
  for (int v = 0; v < rows.rows(); ++v)
    for (int k = 0; k < modal.modes(); ++k) {
      double q = 0;  // the modal force of 1 N along -n, spread by the row
      for (Weights::InnerIterator w(rows, v); w; ++w) q += w.value() * normals.col(v).dot(shapes[k].col(cage[w.col()]));
      c[v] += q * q / (modal.frequencies()[k] * modal.frequencies()[k]);
    }
  return c;
}

// m/N, by row: the behavior model's own compliance at those points of
// the drawn surface, the modal model's in its kept modes.
std::vector<double> surface_compliance(const HybridSpec& spec, const models::massspring::Lattice& lat,
                                       const models::fem::Modal* modal, const Weights& rows,
                                       const std::vector<int>& cage, const Eigen::Matrix3Xd& normals) {
  return modal ? modal_compliance(*modal, rows, cage, normals) : rest_compliance(spec, lat, rows, cage, normals);
}

// The modal model of a spec (BehaviorModel::modal; else none).
std::unique_ptr<models::fem::Modal> modal_of(const HybridSpec& spec) {
  if (spec.behavior_model != BehaviorModel::modal) return nullptr;
  const models::fem::Corotational fem(hybrid_mesh(spec), spec.fem, models::fem::Options{});
  return std::make_unique<models::fem::Modal>(fem, models::fem::ModalOptions{spec.behavior.dt, spec.modes});
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

// N: a first guess at the force for `depth`, along the line through the
// last two (depth, force) found, or at the compliance at rest.
double extrapolated(const std::vector<double>& depths, const std::vector<double>& forces, double depth,
                    double compliance) {
  const std::size_t n = forces.size();
  if (n == 0) return depth / compliance;
  if (n == 1) return forces[0] * depth / depths[0];
  return forces[n - 1] + (depth - depths[n - 1]) * (forces[n - 1] - forces[n - 2]) / (depths[n - 1] - depths[n - 2]);
}

// The behavior model of a spec loaded at one point of its drawn surface
// as touch() loads it: a force along -n spread over masses by a map row,
// settled (Settling) from where the last load left it. (The modal model
// is linear: its answer is its compliance's.)
class Pressed {
 public:
  Pressed(const HybridSpec& spec, std::vector<std::pair<int, double>> row, const Eigen::Vector3d& n, double tolerance)
      : row_(std::move(row)), n_(n), model_(spec, tolerance) {}
  // m: how far the point sinks along -n under `force` (N), settled until
  // that changes by under `change` of itself a step.
  double sink(double force, double change) {
    std::vector<models::massspring::PointForce> loads;
    for (const auto& [m, w] : row_) loads.push_back({m, -force * w * n_});
    double last = 1e300;
    for (int k = 0; k < 1000; ++k) {
      model_.step(loads);
      const double s = at();
      if (std::abs(s - last) <= change * std::abs(s)) break;
      last = s;
    }
    return at();
  }
  // N: the force under which the point sinks `depth`, from `guess`: by
  // secants, within the forces found to sink it less and more once there
  // are both (regula falsi; bisection where the secant leaves them), as
  // the force's growth with depth slows where cells give way.
  double force_for(double depth, double guess) {
    const double tolerance = 1e-2 * depth;
    double f0 = guess, s0 = sink(f0, 3e-4);
    if (std::abs(s0 - depth) <= tolerance) return f0;
    double f1 = s0 > 0 ? f0 * depth / s0 : 2 * f0, s1 = sink(f1, 3e-4);
    double lo = 0, hi = 1e300;  // N: forces that sink it less and more than depth
    auto bracket = [&](double f, double sunk) { sunk < depth ? lo = std::max(lo, f) : hi = std::min(hi, f); };
    bracket(f0, s0), bracket(f1, s1);
    for (int k = 0; k < 40 && std::abs(s1 - depth) > tolerance; ++k) {
      double f = s1 != s0 ? f1 + (depth - s1) * (f1 - f0) / (s1 - s0) : 2 * f1;
      if (!(f > lo && f < hi)) f = hi < 1e300 ? 0.5 * (lo + hi) : 2 * std::max(f1, lo);
      f0 = f1, s0 = s1, f1 = f, s1 = sink(f1, 3e-4);
      bracket(f1, s1);
    }
    return f1;
  }

 private:
  double at() const {
    double s = 0;
    for (const auto& [m, w] : row_) s -= w * n_.dot(model_.state.x.col(m) - model_.rest().col(m));
    return s;
  }
  std::vector<std::pair<int, double>> row_;
  Eigen::Vector3d n_;
  Settling model_;
};

// The point of the drawn surface nearest `point` (rest, world), loaded as
// touch() loads a proxy there: along its inward normal (or `along`, where
// not zero), spread over its face's vertices by their barycentric weights
// and from each over the masses by its map row. `compliance` is what
// Hybrid::force_scale takes for it: its vertices' compliances along that
// direction, weighted alike.
struct SurfaceLoad {
  std::vector<std::pair<int, double>> row;  // mass, weight
  Eigen::Vector3d normal;
  double compliance = 0;  // m/N
};

SurfaceLoad surface_load(const HybridSpec& spec, const models::massspring::Voxels& voxels,
                         const models::massspring::Lattice& lat, const models::fem::Modal* modal,
                         const models::massspring::TriangleMesh& visual, const Cage& cage, const Eigen::Vector3d& point,
                         const Eigen::Vector3d& along = Eigen::Vector3d::Zero()) {
  const MeshProxy mesh(visual.triangles, int(visual.vertices.cols()));
  const SurfacePoint p = mesh.closest(visual.vertices, point);
  const Eigen::Vector3i& face = mesh.triangle(p.face);
  Eigen::Matrix3Xd at(3, 3), normals(3, 3);
  const Eigen::Matrix3Xd all = vertex_normals(visual.vertices, visual.triangles);
  for (int k = 0; k < 3; ++k) {
    at.col(k) = visual.vertices.col(face[k]);
    normals.col(k) = along.isZero() ? Eigen::Vector3d(all.col(face[k])) : Eigen::Vector3d(-along.normalized());
  }
  const Weights rows = map_rows(spec, voxels, cage, at);
  const std::vector<double> c = surface_compliance(spec, lat, modal, rows, cage.masses, normals);
  SurfaceLoad l;
  std::map<int, double> by_mass;
  for (int k = 0; k < 3; ++k) {
    for (Weights::InnerIterator w(rows, k); w; ++w) by_mass[cage.masses[w.col()]] += p.bary[k] * w.value();
    l.compliance += p.bary[k] * c[k];
  }
  l.row.assign(by_mass.begin(), by_mass.end());
  l.normal = along.isZero() ? mesh.normal(visual.vertices, p) : Eigen::Vector3d(-along.normalized());
  return l;
}

// N, by depth (increasing): the forces under which a surface load's
// point sinks that deep, pressed deeper step by step as a stylus presses
// (past a snap-through a force has two depths, and the press follows the
// one it is on); the modal model's, its compliance's.
std::vector<double> surface_forces(const HybridSpec& spec, const models::fem::Modal* modal, const SurfaceLoad& l,
                                   const std::vector<double>& depths) {
  std::vector<double> f;
  if (modal) {
    for (const double d : depths) f.push_back(d / l.compliance);
    return f;
  }
  // A loose CG tolerance: each settle step is then a rougher Newton step,
  // but settling goes on until the sink stops changing, so where it ends
  // is the same (the forces agree to 4 digits with 1e-5) in under half
  // the time.
  Pressed pressed(spec, l.row, l.normal, 1e-3);
  std::vector<double> at, force;  // m and N: every depth pressed to, and its force
  for (const double d : depths) {
    const double last = at.empty() ? 0 : at.back();
    const int steps = std::max(1, int(std::ceil((d - last) / (0.05 * depths.back()))));
    for (int k = 1; k <= steps; ++k) {
      const double x = last + (d - last) * k / steps;
      force.push_back(pressed.force_for(x, extrapolated(at, force, x, l.compliance)));
      at.push_back(x);
    }
    f.push_back(force.back());
  }
  return f;
}

}  // namespace

std::vector<double> behavior_surface_force(const HybridSpec& spec, const Eigen::Vector3d& point,
                                           const std::vector<double>& depths, const Eigen::Vector3d& along) {
  need_hybrid(point.allFinite(), "the point must be finite");
  need_hybrid(along.allFinite(), "the direction must be finite");
  for (std::size_t j = 0; j < depths.size(); ++j)
    need_hybrid(std::isfinite(depths[j]) && depths[j] > (j > 0 ? depths[j - 1] : 0),
                "the depths must be finite, > 0 and increasing");
  const models::massspring::Voxels voxels = hybrid_voxels(spec);
  const models::massspring::Lattice lat = hybrid_masses(spec);
  const models::massspring::TriangleMesh visual = hybrid_visual(spec);
  const Cage cage = map_cage(spec, voxels, lat, visual);
  const std::unique_ptr<models::fem::Modal> modal = modal_of(spec);
  return surface_forces(spec, modal.get(), surface_load(spec, voxels, lat, modal.get(), visual, cage, point, along),
                        depths);
}

ForceGain force_gain(const HybridSpec& spec, const Weights& map) {
  const models::massspring::Voxels voxels = hybrid_voxels(spec);
  const models::massspring::Lattice lat = hybrid_masses(spec);
  const models::massspring::TriangleMesh visual = hybrid_visual(spec);
  const Cage cage = map_cage(spec, voxels, lat, visual);
  const double extent = rest_box(spec).sizes().minCoeff();
  ForceGain gain;
  // Closer where the S-Chain's growth is steepest: a stiff side's short
  // ranges move a new ring of chains every few tenths of a millimetre.
  for (const double f : {0.02, 0.03, 0.04, 0.06, 0.08, 0.1,  0.12, 0.14, 0.16, 0.2, 0.24,
                         0.28, 0.32, 0.4,  0.48, 0.56, 0.64, 0.72, 0.8,  0.88, 1.0})
    gain.depth.push_back(0.25 * extent * f);
  // Each side's gain element's point of the drawn surface, pressed in turn
  // to every depth, and its chains pressed as deep.
  const std::unique_ptr<models::fem::Modal> modal = modal_of(spec);
  const SChain chain(hybrid_chains(spec), spec.relax_rate, spec.limit_stiffness);
  auto side = [&](bool stiff, double* compliance) {
    const SurfaceLoad l =
        surface_load(spec, voxels, lat, modal.get(), visual, cage, find_gain_point(spec, voxels, chain, stiff).first);
    *compliance = l.compliance;
    return surface_forces(spec, modal.get(), l, gain.depth);
  };
  gain.soft = side(false, &gain.soft_compliance);
  if (spec.stiff_ratio != 1) gain.stiff = side(true, &gain.stiff_compliance);
  need_hybrid(
      map.size() == 0 || (map.rows() == visual.vertices.cols() && map.cols() == Eigen::Index(cage.masses.size())),
      "the visual map given must have a row per visual vertex and a column per cage mass");
  if (lat.size() <= ForceGain::kMostMasses)
    gain.compliance =
        surface_compliance(spec, lat, modal.get(), map.size() ? map : map_rows(spec, voxels, cage, visual.vertices),
                           cage.masses, vertex_normals(visual.vertices, visual.triangles));
  return gain;
}

Weights mvc_map(const HybridSpec& spec, const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                const Eigen::Matrix3Xd& points) {
  Weights w = mean_value_weights(cage, triangles, points);
  return spec.map == VisualMap::mvc_sparse ? truncate(w, spec.keep) : w;
}

namespace {

// force_gain, once per process for each spec that shapes it: tests and
// benches build many hybrids of one spec.
ForceGain remembered_gain(const HybridSpec& s, const Weights& map) {
  std::ostringstream o;
  o << std::hexfloat;
  for (const double v : gain_inputs(s)) o << v << ' ';
  static std::mutex m;
  static std::map<std::string, ForceGain> seen;
  {
    const std::lock_guard<std::mutex> l(m);
    if (const auto it = seen.find(o.str()); it != seen.end()) return it->second;
  }
  ForceGain g = force_gain(s, map);
  const std::lock_guard<std::mutex> l(m);
  return seen.emplace(o.str(), std::move(g)).first->second;
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
    need_hybrid(weights_.rows() == visual_.vertices.cols() && weights_.cols() == cage.rest.cols(),
                "the visual map must have a row per visual vertex and a column per cage vertex");
  }
  gain_ = gain ? gain(spec, weights_) : remembered_gain(spec, weights_);
  const std::size_t k = gain_.depth.size();
  need_hybrid(k >= 2 && gain_.soft.size() == k && (gain_.stiff.empty() || gain_.stiff.size() == k),
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
  need_hybrid(gain_elements_[0] >= 0 && gain_elements_[1] >= 0, "no chain element at a gain point");
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
  need_hybrid(dt > 0 && std::isfinite(dt), "dt must be finite and > 0");
  need_hybrid(hip.allFinite(), "the haptic point must be finite");
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
  double chain = power_between(gain_.depth, &chain_force_[std::size_t(e) * nd], depth);
  if (!(chain > 0)) chain = power_between(gain_.depth, &chain_force_[std::size_t(gain_elements_[side]) * nd], depth);
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
