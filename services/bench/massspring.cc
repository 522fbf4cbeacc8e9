// bench massspring: every integrator, with and without adaptive active
// masses, and MuJoCo 2.2.2 on the same lattices, as time per simulated
// second against error from a converged reference.
//
// Scene: a lattice pressed at one mass for 0.1 s, then released; 0.2 s are
// simulated and the positions sampled every 20 ms. rel_error is the
// root-sum-square distance of those samples from the reference's, over
// the reference's root-sum-square displacement. The reference is RK4 on the
// full model at a sixteenth of its stable step; the `reference` row reports
// its own change when that step is halved (ref_self_error), and errors that
// differ by less than that count as equal.
//
// recovery: seed 000's elastic surfaces as the default scene builds them
// (a 4 cm sheet of 21 x 21 masses, a 2 cm dome of 12 rings), at their
// stiffness and 4 times it, with their bending hinges and without
// (`membrane`): the HIP presses 7 mm over 0.2 s, holds 0.5 s and leaves;
// off_1s_mm and off_2s_mm are the largest vertex distance from rest that
// long after the release, tick_us the touch (contact and behavior step)
// per servo tick while pressed, force_n the force felt at the end of the
// hold.
//
// against_fem: a continuum reference. The lattice is a
// 4 cm cube of 5^3 masses with springs along its edges and both face
// diagonals, whose elastic constants are those of an isotropic solid of
// Young's modulus 2.5 k / a and Poisson's ratio 1/4; the corotational FEM
// (models/fem) of that solid, of the lattice's mass and mass damping drag / m,
// on a mesh refined `refinement` times and stepped by the trapezoidal
// rule at 0.1 ms, is the reference. The top face's centre 2 x 2 cm patch is
// pressed with 0.2 N for 0.1 s, then let go (scene `press`; without
// --quick also pulled up so, scene `pull`); rel_error as for `step`, at
// the lattice's masses (the fine mesh's nodes in the same places). The
// `fem_reference` row reports the reference's own change when its mesh is
// one refinement coarser (ref_space_error) and its step twice as long
// (ref_time_error); against_fem_static the same press settled. Beside the
// springs, the FEM on the lattice's own nodes and Bullet's soft body, the
// `modal` rows are that FEM's linear modal reduction (models/fem/modal.h)
// over the modes kept and the step.
//
// adaptive: the adaptive model against the full one with the same
// integrator and step, as the threshold falls, on a 12^3 box (anchored
// floor, 50 or 5000 N/m springs) pressed with 0.3 N at its top for 0.2 s,
// at a video-rate step (1/30 s: many substeps for the explicit
// integrators, one solve for the implicit ones) and at 0.5 ms with stiff
// springs: rel_error as for `step`, simulated_fraction the most masses
// simulated at once, ms the adaptive run's wall time against the full
// one's (`full_ms`).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

#include "models/deformable/elastic_surface.h"
#include "models/fem/corotational.h"
#include "models/fem/modal.h"
#include "models/massspring/quartet.h"
#include "models/massspring/simulator.h"
#include "services/bench/bench.h"
#include "services/bench/bullet_soft.h"
#include "services/bench/mujoco_lattice.h"

namespace hcosim::services::bench {
namespace {

namespace ms = hcosim::models::massspring;
namespace fem = hcosim::models::fem;

constexpr double kDuration = 0.2, kPress = 0.1, kSample = 0.02;  // s

struct Scene {
  std::string name;  // e.g. box1000
  std::string shape;
  ms::Lattice lattice;
  int contact = 0;
  Eigen::Vector3d force;
};

// n^3 masses 1 cm apart, 1 g each, 50 N/m springs, air friction; the floor
// is anchored and the middle of the top face is pressed with 0.5 N.
Scene box(int n) {
  ms::Material m;
  m.mass = 1e-3, m.k = 50, m.drag = 5e-3;
  Scene s{"box" + std::to_string(n * n * n), "box", ms::make_box(n, n, n, 0.01, m), 0, {0, 0, -0.5}};
  ms::anchor_where(s.lattice, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  s.contact = n / 2 + n * (n / 2 + n * (n - 1));
  return s;
}

// Seed 000's semi-sphere, radius 10 cm, pressed at its pole with 0.05 N.
Scene dome(int rings, int segments) {
  ms::Material m;
  m.mass = 1e-3, m.k = 50, m.drag = 5e-3;
  ms::Lattice l = ms::make_semisphere(rings, segments, 0.1, m);
  const int pole = l.size() - 1;
  return {"dome" + std::to_string(l.size()), "semisphere", std::move(l), pole, {0, 0, -0.05}};
}

struct Trace {
  std::vector<Eigen::Matrix3Xd> samples;
  double wall_s = 0;
  double simulated = 0;  // mean fraction of masses integrated per step
  int substeps = 1;
};

int steps_of(double dt) { return int(std::lround(kDuration / dt)); }

// Steps `step(k, loaded)` over the scene's timeline, sampling `positions()`.
template <class Step, class Positions>
Trace timeline(double dt, Step&& step, Positions&& positions) {
  Trace t;
  const int n = steps_of(dt), every = int(std::lround(kSample / dt));
  double wall = 0;
  for (int k = 0; k < n; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    step(k * dt < kPress - 1e-12);
    wall += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if ((k + 1) % every == 0) t.samples.push_back(positions());
  }
  t.wall_s = wall;
  return t;
}

Trace run_ours(const Scene& sc, const ms::Options& o) {
  ms::Simulator sim(sc.lattice, o);
  ms::State s = ms::rest_state(sc.lattice);
  const std::vector<ms::PointForce> press{{sc.contact, sc.force}}, none;
  double simulated = 0;
  Trace t = timeline(
      o.dt, [&](bool loaded) { simulated += sim.step(s, loaded ? press : none).simulated; }, [&] { return s.x; });
  t.simulated = simulated / steps_of(o.dt) / sc.lattice.size();
  t.substeps = sim.substeps();
  return t;
}

Trace run_mujoco(const Scene& sc, double dt, const char* integrator) {
  MujocoLattice mj(sc.lattice, dt, integrator);
  const std::vector<ms::PointForce> press{{sc.contact, sc.force}}, none;
  Trace t = timeline(
      dt, [&](bool loaded) { mj.step(loaded ? press : none); }, [&] { return mj.positions(); });
  t.simulated = 1;
  return t;
}

double rel_error(const Scene& sc, const Trace& got, const Trace& ref) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ref.samples.size(); ++i) {
    num += (got.samples[i] - ref.samples[i]).squaredNorm();
    den += (ref.samples[i] - sc.lattice.rest).squaredNorm();
  }
  return std::sqrt(num / den);
}

std::string fmt(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// Median wall time over `reps` runs (one if a run takes over 2 s).
template <class Run>
Trace measure(Run&& run, int reps) {
  Trace first = run();
  if (reps <= 1 || first.wall_s > 2) return first;
  std::vector<double> walls{first.wall_s};
  for (int r = 1; r < reps; ++r) walls.push_back(run().wall_s);
  std::sort(walls.begin(), walls.end());
  first.wall_s = walls[walls.size() / 2];
  return first;
}

struct Config {
  ms::Integrator integrator;
  double dt, threshold;
};

std::vector<Row> scene_rows(const Scene& sc, const Context& c) {
  const int reps = 3;
  const double budget_s = c.quick ? 10 : 90;  // longest single run we start
  std::vector<Row> rows;
  const ms::Spectrum spec = ms::bound_spectrum(sc.lattice);
  const double stable = ms::stable_step(ms::Integrator::rk4, spec);
  const double ref_dt = kSample / std::ceil(kSample / (stable / 16));
  progress(sc.name + ": reference, RK4 at dt " + fmt(ref_dt) + " s and half that");
  ms::Options ro;
  ro.integrator = ms::Integrator::rk4;
  ro.dt = ref_dt;
  const Trace ref = run_ours(sc, ro);
  ro.dt = ref_dt / 2;
  const Trace finer = run_ours(sc, ro);
  const double ref_self_error = rel_error(sc, finer, ref);
  rows.push_back({"reference",
                  {{"lattice", sc.name},
                   {"shape", sc.shape},
                   {"masses", double(sc.lattice.size())},
                   {"springs", double(sc.lattice.springs.size())},
                   {"integrator", std::string("rk4")},
                   {"dt", ref_dt}},
                  {{"ref_self_error", ref_self_error}, {"omega_max_rad_s", spec.omega_max}}});

  std::vector<Config> configs;
  const std::vector<double> explicit_dt =
      c.quick ? std::vector<double>{1e-3, 5e-4} : std::vector<double>{1e-3, 5e-4, 2.5e-4};
  const std::vector<double> implicit_dt =
      c.quick ? std::vector<double>{4e-3, 1e-3} : std::vector<double>{4e-3, 2e-3, 1e-3, 5e-4};
  for (auto in : {ms::Integrator::symplectic_euler, ms::Integrator::velocity_verlet, ms::Integrator::rk4})
    for (double dt : explicit_dt) configs.push_back({in, dt, 0});
  for (auto in : {ms::Integrator::implicit_euler, ms::Integrator::local_global})
    for (double dt : implicit_dt) configs.push_back({in, dt, 0});
  for (double th : c.quick ? std::vector<double>{1e-8} : std::vector<double>{1e-10, 1e-8, 1e-6}) {
    configs.push_back({ms::Integrator::symplectic_euler, 5e-4, th});
    configs.push_back({ms::Integrator::velocity_verlet, 1e-3, th});
  }
  std::map<std::string, double> over_budget;  // label and threshold -> dt that was
  auto add_row = [&](const std::string& integrator, double dt, double threshold, const Trace& t,
                     const std::string& mujoco_integrator = "") {
    Row r{"step",
          {{"lattice", sc.name},
           {"shape", sc.shape},
           {"masses", double(sc.lattice.size())},
           {"integrator", integrator},
           {"dt", dt},
           {"threshold", threshold}},
          {{"ms_per_sim_s", 1e3 * t.wall_s / kDuration},
           {"rel_error", rel_error(sc, t, ref)},
           {"simulated_fraction", t.simulated},
           {"substeps", double(t.substeps)}}};
    if (!mujoco_integrator.empty()) r.params.push_back({"mujoco_integrator", mujoco_integrator});
    rows.push_back(r);
  };
  for (const Config& cf : configs) {
    ms::Options o;
    o.integrator = cf.integrator;
    o.dt = cf.dt;
    o.threshold = cf.threshold;
    const std::string label = std::string(ms::name(cf.integrator)) + (cf.threshold > 0 ? " adaptive" : "");
    // A smaller dt of a configuration already over budget only takes longer.
    const std::string family = label + " " + fmt(cf.threshold);
    if (over_budget.count(family) && cf.dt < over_budget[family]) {
      progress(sc.name + ": skip " + label + " dt " + fmt(cf.dt) + ": dt " + fmt(over_budget[family]) +
               " was already over the budget");
      continue;
    }
    // A few steps first: skip what would take longer than the budget.
    {
      ms::Simulator probe(sc.lattice, o);
      ms::State s = ms::rest_state(sc.lattice);
      const auto t0 = std::chrono::steady_clock::now();
      for (int k = 0; k < 3; ++k) probe.step(s, {{sc.contact, sc.force}});
      const double per_step = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / 3;
      if (per_step * steps_of(cf.dt) > budget_s) {
        over_budget[family] = cf.dt;
        progress(sc.name + ": skip " + label + " dt " + fmt(cf.dt) + ": about " + fmt(per_step * steps_of(cf.dt)) +
                 " s, over the " + fmt(budget_s) + " s budget");
        continue;
      }
    }
    progress(sc.name + ": " + label + " dt " + fmt(cf.dt) +
             (cf.threshold > 0 ? " threshold " + fmt(cf.threshold) : ""));
    add_row(ms::name(cf.integrator), cf.dt, cf.threshold, measure([&] { return run_ours(sc, o); }, reps));
  }
  // MuJoCo on the same lattice, where version 2.2.2 can hold it.
  const double bytes = MujocoLattice::data_bytes(sc.lattice);
  const std::size_t first_mujoco = rows.size();
  if (bytes > 1.9e9) {
    progress(sc.name + ": skip mujoco: its dense tendon Jacobian needs " + fmt(bytes / 1e9) +
             " GB, over the 2 GiB int-sized mjData buffer of MuJoCo 2.2.2");
  } else {
    for (const char* integrator : {"Euler", "RK4"})
      for (double dt : explicit_dt) {
        progress(sc.name + ": mujoco " + integrator + " dt " + fmt(dt));
        add_row("mujoco", dt, 0, measure([&] { return run_mujoco(sc, dt, integrator); }, reps), integrator);
      }
  }
  // Speed-up at equal or lower error: for each MuJoCo row, our fastest row
  // whose error is no larger, up to the reference's own error.
  for (std::size_t m = first_mujoco; m < rows.size(); ++m) {
    const double mj_ms = rows[m].metrics[0].second, mj_err = rows[m].metrics[1].second;
    const Row* best = nullptr;
    for (std::size_t k = 1; k < first_mujoco; ++k)
      if (rows[k].metrics[1].second <= mj_err + ref_self_error &&
          (!best || rows[k].metrics[0].second < best->metrics[0].second))
        best = &rows[k];
    if (!best) continue;
    rows[m].metrics.push_back({"speedup_at_equal_error", mj_ms / best->metrics[0].second});
    std::string match;
    for (const auto& [k, v] : best->params)
      if (k == "integrator" || k == "dt" || k == "threshold") match += (match.empty() ? "" : " ") + k + "=" + text(v);
    rows[m].params.push_back({"matched_by", match});
  }
  return rows;
}

Row recovery_row(models::deformable::Shape shape, ms::Integrator integrator, double stiffer, bool hinges) {
  namespace md = models::deformable;
  md::SurfaceSpec s;
  s.shape = shape;
  s.size = shape == md::Shape::sheet ? 0.04 : 0.02;
  s.resolution = shape == md::Shape::sheet ? 21 : 12;
  s.material.k *= stiffer;
  if (!hinges) s.bending = 0;
  s.options.integrator = integrator;
  s.options.dt = 1e-3;
  md::ElasticSurface o(s);
  const double top = shape == md::Shape::sheet ? 0 : s.size;
  std::vector<double> tick_us;
  md::Touch t;
  for (int k = 0; k < 700; ++k) {
    const auto t0 = std::chrono::steady_clock::now();
    t = o.touch(1e-3, Eigen::Vector3d(0.0003, 0.0002, top + 0.002 - 0.009 * std::min(1.0, k / 200.0)), false);
    tick_us.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count());
  }
  double off[2] = {0, 0};
  for (int k = 1; k <= 2000; ++k) {
    o.touch(1e-3, Eigen::Vector3d(0, 0, top + 0.05), false);
    if (k % 1000 == 0) off[k / 1000 - 1] = (o.state().x - o.behavior().lattice().rest).colwise().norm().maxCoeff();
  }
  std::sort(tick_us.begin(), tick_us.end());
  return {"recovery",
          {{"shape", std::string(md::name(shape))},
           {"model", std::string(hinges ? "hinges" : "membrane")},
           {"integrator", std::string(ms::name(integrator))},
           {"stiffness", s.material.k},
           {"bending", s.bending},
           {"masses", double(o.behavior().lattice().size())}},
          {{"off_1s_mm", off[0] * 1e3},
           {"off_2s_mm", off[1] * 1e3},
           {"tick_us_p50", tick_us[tick_us.size() / 2]},
           {"tick_us_p99", tick_us[std::size_t(0.99 * double(tick_us.size() - 1) + 0.5)]},
           {"substeps", double(o.behavior().substeps())},
           {"force_n", t.force.norm()}}};
}

std::vector<Row> recovery_rows(const Context& c) {
  std::vector<Row> rows;
  const std::vector<ms::Integrator> integrators =
      c.quick ? std::vector<ms::Integrator>{ms::Integrator::symplectic_euler}
              : std::vector<ms::Integrator>{ms::Integrator::symplectic_euler, ms::Integrator::velocity_verlet,
                                            ms::Integrator::rk4, ms::Integrator::implicit_euler,
                                            ms::Integrator::local_global};
  for (const auto shape : {models::deformable::Shape::semisphere, models::deformable::Shape::sheet})
    for (const ms::Integrator integrator : integrators)
      for (const double stiffer : c.quick ? std::vector<double>{1} : std::vector<double>{1, 4})
        for (const bool hinges : {true, false}) {
          progress(std::string("massspring recovery: ") + models::deformable::name(shape) + ", " +
                   ms::name(integrator) + ", k x" + fmt(stiffer) + (hinges ? "" : ", no hinges"));
          rows.push_back(recovery_row(shape, integrator, stiffer, hinges));
        }
  return rows;
}

// The cube of against_fem: kCells cells of kSpacing a side.
constexpr int kCells = 4;
constexpr double kSpacing = 0.01, kPressN = 0.2;

// The seed's scenes on the cube's top (press, pull; each then released):
// the load's sign along z.
struct TopLoad {
  const char* name;
  double sign;
};
constexpr TopLoad kPressLoad{"press", -1}, kPullLoad{"pull", 1};

// The load of `scene` on a box of nodes `spacing` apart: kPressN along z,
// spread over the top face's centre patch (two cells of kSpacing a side)
// by trapezoid weights along x and y, so that every refinement loads the
// same area the same way.
std::vector<ms::PointForce> patch_load(const Eigen::Matrix3Xd& rest, double spacing, const TopLoad& scene) {
  const double top = rest.row(2).maxCoeff(), centre = 0.5 * kCells * kSpacing;
  auto weight = [&](double t) {
    const double d = std::abs(t - centre);
    return d < kSpacing - 0.25 * spacing ? 1.0 : d < kSpacing + 0.25 * spacing ? 0.5 : 0.0;
  };
  std::vector<ms::PointForce> loads;
  double sum = 0;
  for (int i = 0; i < rest.cols(); ++i) {
    const double w = rest(2, i) > top - 1e-9 ? weight(rest(0, i)) * weight(rest(1, i)) : 0;
    if (w > 0) loads.push_back({i, Eigen::Vector3d(0, 0, w)}), sum += w;
  }
  for (ms::PointForce& p : loads) p.force *= scene.sign * kPressN / sum;
  return loads;
}

ms::Material cube_material() {
  ms::Material m;
  m.mass = 1e-3, m.k = 50, m.drag = 5e-3;
  return m;
}

// The continuum the lattice stands for (see against_fem above): its
// elastic constants, the lattice's whole mass over the cube's volume, and
// the drag as mass damping.
fem::Material continuum(const ms::Material& m) {
  fem::Material f;
  f.young = 2.5 * m.k / kSpacing;
  f.poisson = 0.25;
  f.density = m.mass * std::pow(kCells + 1, 3) / std::pow(kCells * kSpacing, 3);
  f.alpha = m.drag / m.mass;
  return f;
}

// The cube's lattice: springs along the edges and both face diagonals,
// its floor anchored.
ms::Lattice cube_lattice() {
  ms::Lattice l = ms::make_box(kCells + 1, kCells + 1, kCells + 1, kSpacing, cube_material(), ms::Shear::both);
  ms::anchor_where(l, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
  return l;
}

// The FEM cube refined `r` times, its floor anchored, and its nodes where
// the lattice's masses are, in the lattice's order.
struct FemCube {
  fem::Mesh mesh;
  std::vector<int> at;
  Eigen::Matrix3Xd sample(const Eigen::Matrix3Xd& x) const {
    Eigen::Matrix3Xd out(3, at.size());
    for (std::size_t q = 0; q < at.size(); ++q) out.col(q) = x.col(at[q]);
    return out;
  }
};

FemCube fem_cube(int r) {
  const int n = r * kCells + 1;
  FemCube c{fem::box_mesh(n, n, n, kSpacing / r), {}};
  for (int i = 0; i < c.mesh.size(); ++i) c.mesh.anchored[i] = c.mesh.rest(2, i) < 1e-12;
  for (int k = 0; k <= kCells; ++k)
    for (int j = 0; j <= kCells; ++j)
      for (int i = 0; i <= kCells; ++i) c.at.push_back(r * i + n * (r * j + n * r * k));
  return c;
}

// The FEM cube refined `r` times under `scene`, stepped at dt by
// `scheme`; samples at the lattice's masses.
Trace run_fem(int r, double dt, fem::Scheme scheme, const TopLoad& scene) {
  const FemCube c = fem_cube(r);
  fem::Options o;
  o.dt = dt, o.scheme = scheme;
  fem::Corotational f(c.mesh, continuum(cube_material()), o);
  ms::State s = fem::rest_state(c.mesh);
  const std::vector<ms::PointForce> load = patch_load(c.mesh.rest, kSpacing / r, scene), none;
  return timeline(
      dt, [&](bool loaded) { f.step(s, loaded ? load : none); }, [&] { return c.sample(s.x); });
}

// The positions at the lattice's masses once the scene's load has
// settled (quasi-static: implicit steps of 1 s), for the springs or the
// FEM refined r times (r = 0: the springs).
Eigen::Matrix3Xd settled(int r, const TopLoad& scene) {
  if (r == 0) {
    const ms::Lattice l = cube_lattice();
    ms::Options o;
    o.integrator = ms::Integrator::implicit_euler, o.dt = 1, o.tolerance = 1e-10;
    ms::Simulator sim(l, o);
    ms::State s = ms::rest_state(l);
    const std::vector<ms::PointForce> load = patch_load(l.rest, kSpacing, scene);
    for (int k = 0; k < 200; ++k) sim.step(s, load);
    return s.x;
  }
  const FemCube c = fem_cube(r);
  fem::Options o;
  o.dt = 1, o.tolerance = 1e-10;
  fem::Corotational f(c.mesh, continuum(cube_material()), o);
  ms::State s = fem::rest_state(c.mesh);
  const std::vector<ms::PointForce> load = patch_load(c.mesh.rest, kSpacing / r, scene);
  for (int k = 0; k < 100; ++k) f.step(s, load);
  return c.sample(s.x);
}

double trace_error(const Trace& got, const Trace& ref, const Eigen::Matrix3Xd& rest) {
  double num = 0, den = 0;
  for (std::size_t i = 0; i < ref.samples.size(); ++i) {
    num += (got.samples[i] - ref.samples[i]).squaredNorm();
    den += (ref.samples[i] - rest).squaredNorm();
  }
  return std::sqrt(num / den);
}

// against_fem rows of Bullet's soft body on the same nodes and tetrahedra,
// masses and drag (kDP = drag dt / m), over its stiffness coefficient and
// iterations.
void add_bullet_rows(std::vector<Row>& rows, const std::string& what, const ms::Lattice& l,
                     const std::vector<ms::PointForce>& load, const Trace& ref) {
  const std::vector<ms::PointForce> none;
  const Eigen::VectorXd masses = l.mass;
  for (const double stiffness : {0.1, 0.5, 1.0})
    for (const int iterations : {1, 4, 16}) {
      progress(what + "Bullet's soft body, kLST " + fmt(stiffness) + ", " + std::to_string(iterations) + " iterations");
      BulletSoftSettings bs;
      bs.stiffness = stiffness, bs.iterations = iterations, bs.dt = 1e-3;
      bs.damping = cube_material().drag / cube_material().mass * bs.dt;
      const Trace t = measure(
          [&] {
            BulletSoft body(l.rest, ms::box_tetrahedra(kCells + 1, kCells + 1, kCells + 1), masses, l.anchored, bs);
            return timeline(
                bs.dt, [&](bool loaded) { body.step(loaded ? load : none); }, [&] { return body.positions(); });
          },
          3);
      rows.push_back({"against_fem",
                      {{"model", std::string("bullet")},
                       {"integrator", std::string("btSoftBody")},
                       {"dt", bs.dt},
                       {"threshold", 0.0},
                       {"bullet_stiffness", stiffness},
                       {"bullet_iterations", double(iterations)}},
                      {{"rel_error", trace_error(t, ref, l.rest)},
                       {"ms_per_sim_s", t.wall_s * 1e3 / kDuration},
                       {"substeps", 1.0}}});
    }
}

// against_fem rows of the FEM's linear modal reduction (models/fem/modal.h)
// on the same nodes and solid, over the modes kept and the step: each step
// exact for a load held over it, as this scene's is.
void add_modal_rows(std::vector<Row>& rows, const std::string& what, const TopLoad& scene, const fem::Material& cont,
                    const Trace& ref, const Eigen::Matrix3Xd& rest) {
  const std::vector<ms::PointForce> none;
  const FemCube nodes = fem_cube(1);
  const fem::Corotational linearised(nodes.mesh, cont, {});
  const std::vector<ms::PointForce> node_load = patch_load(nodes.mesh.rest, kSpacing, scene);
  for (const int modes : {8, 32, 3 * int(std::count(nodes.mesh.anchored.begin(), nodes.mesh.anchored.end(), 0))})
    for (const double dt : {1e-3, 5e-3, 2e-2}) {
      progress(what + "the FEM's " + std::to_string(modes) + " lowest modes, dt " + fmt(dt));
      const fem::Modal modal(linearised, fem::ModalOptions{dt, modes});
      const Trace t = measure(
          [&] {
            ms::State st = fem::rest_state(nodes.mesh);
            return timeline(
                dt, [&](bool loaded) { modal.step(st, loaded ? node_load : none); },
                [&] { return nodes.sample(st.x); });
          },
          3);
      rows.push_back({"against_fem",
                      {{"model", std::string("modal")},
                       {"integrator", std::string("exact")},
                       {"dt", dt},
                       {"threshold", 0.0},
                       {"modes", double(modes)}},
                      {{"rel_error", trace_error(t, ref, rest)},
                       {"ms_per_sim_s", t.wall_s * 1e3 / kDuration},
                       {"substeps", 1.0}}});
    }
}

// Each Bullet row: its time over that of our fastest row (springs, FEM or
// modes) whose error is no larger; 0 where none of ours is as close.
// against_fem rows: params[0] the model; metrics rel_error, ms_per_sim_s.
void match_bullet(std::vector<Row>& rows) {
  auto model = [](const Row& r) { return std::get<std::string>(r.params[0].second); };
  for (Row& b : rows) {
    if (b.name != "against_fem" || model(b) != "bullet") continue;
    const Row* best = nullptr;
    for (const Row& o : rows)
      if (o.name == "against_fem" && model(o) != "bullet" && o.metrics[0].second <= b.metrics[0].second &&
          (!best || o.metrics[1].second < best->metrics[1].second))
        best = &o;
    b.metrics.push_back({"speedup_at_equal_error", best ? b.metrics[1].second / best->metrics[1].second : 0.0});
    std::string match = best ? "" : "none";
    if (best)
      for (const auto& [k, v] : best->params)
        if (k == "model" || k == "integrator" || k == "dt" || k == "threshold" || k == "modes")
          match += (match.empty() ? "" : " ") + k + "=" + text(v);
    b.params.push_back({"matched_by", match});
  }
}

// One scene's rows of against_fem, fem_reference and against_fem_static,
// each with its `scene` param last.
std::vector<Row> fem_rows(const Context& c, const TopLoad& scene) {
  const int refinement = c.quick ? 3 : 4;
  const double ref_dt = 1e-4;
  const std::string what = std::string("massspring against_fem, ") + scene.name + ": ";
  progress(what + "the FEM reference, refinement " + std::to_string(refinement));
  const Trace ref = run_fem(refinement, ref_dt, fem::Scheme::trapezoidal, scene);
  const Trace coarser = run_fem(refinement - 1, ref_dt, fem::Scheme::trapezoidal, scene);
  const Trace longer = run_fem(refinement, 2 * ref_dt, fem::Scheme::trapezoidal, scene);
  const ms::Lattice l = cube_lattice();
  const fem::Material cont = continuum(cube_material());
  std::vector<Row> rows;
  progress(what + "settled loads");
  const Eigen::Matrix3Xd still = settled(refinement, scene), still_coarser = settled(refinement - 1, scene);
  auto static_error = [&](const Eigen::Matrix3Xd& x) { return (x - still).norm() / (still - l.rest).norm(); };
  rows.push_back({"fem_reference",
                  {{"cells", double(kCells)},
                   {"refinement", double(refinement)},
                   {"nodes", std::pow(refinement * kCells + 1, 3)},
                   {"scheme", std::string("trapezoidal")},
                   {"dt", ref_dt}},
                  {{"young_pa", cont.young},
                   {"poisson", cont.poisson},
                   {"ref_space_error", trace_error(coarser, ref, l.rest)},
                   {"ref_time_error", trace_error(longer, ref, l.rest)},
                   {"ref_static_error", static_error(still_coarser)},
                   {"ms_per_sim_s", ref.wall_s * 1e3 / kDuration}}});
  const std::vector<ms::PointForce> load = patch_load(l.rest, kSpacing, scene), none;
  auto add = [&](const std::string& model, const std::string& integrator, double dt, double threshold, const Trace& t) {
    rows.push_back({"against_fem",
                    {{"model", model}, {"integrator", integrator}, {"dt", dt}, {"threshold", threshold}},
                    {{"rel_error", trace_error(t, ref, l.rest)},
                     {"ms_per_sim_s", t.wall_s * 1e3 / kDuration},
                     {"substeps", double(t.substeps)}}});
  };
  struct Run {
    ms::Integrator integrator;
    double dt, threshold;
  };
  for (const Run cf :
       {Run{ms::Integrator::symplectic_euler, 1e-3, 0}, Run{ms::Integrator::symplectic_euler, 1e-3, 1e-10},
        Run{ms::Integrator::velocity_verlet, 1e-3, 0}, Run{ms::Integrator::velocity_verlet, 1e-3, 1e-10},
        Run{ms::Integrator::rk4, 1e-3, 0}, Run{ms::Integrator::rk4, 1e-4, 0},
        Run{ms::Integrator::implicit_euler, 1e-3, 0}, Run{ms::Integrator::implicit_euler, 5e-3, 0},
        Run{ms::Integrator::implicit_euler, 2e-2, 0}, Run{ms::Integrator::local_global, 1e-3, 0},
        Run{ms::Integrator::local_global, 5e-3, 0}, Run{ms::Integrator::local_global, 2e-2, 0}}) {
    ms::Options o;
    o.integrator = cf.integrator, o.dt = cf.dt, o.threshold = cf.threshold;
    const double dt = cf.dt;
    if (std::abs(kSample / dt - std::round(kSample / dt)) > 1e-9) continue;
    progress(what + ms::name(cf.integrator) + ", dt " + fmt(dt));
    Trace t = measure(
        [&] {
          ms::Simulator sim(l, o);
          ms::State st = ms::rest_state(l);
          int substeps = 1;
          Trace tr = timeline(
              dt, [&](bool loaded) { substeps = std::max(substeps, sim.step(st, loaded ? load : none).substeps); },
              [&] { return st.x; });
          tr.substeps = substeps;
          return tr;
        },
        3);
    add("springs", ms::name(cf.integrator), dt, cf.threshold, t);
  }
  add_bullet_rows(rows, what, l, load, ref);
  for (const int r : {0, 1})
    rows.push_back({"against_fem_static",
                    {{"model", std::string(r == 0 ? "springs" : "fem")}},
                    {{"rel_error", static_error(settled(r, scene))}}});
  for (const fem::Scheme scheme : {fem::Scheme::implicit_euler, fem::Scheme::trapezoidal})
    for (const double dt : {1e-3, 5e-3, 2e-2}) {
      const char* name = scheme == fem::Scheme::trapezoidal ? "trapezoidal" : "implicit_euler";
      progress(what + "the FEM on the lattice's nodes, " + name + ", dt " + fmt(dt));
      add("fem", name, dt, 0, measure([&] { return run_fem(1, dt, scheme, scene); }, 3));
    }
  add_modal_rows(rows, what, scene, cont, ref, l.rest);
  match_bullet(rows);
  for (Row& r : rows) r.params.push_back({"scene", std::string(scene.name)});
  return rows;
}

// against_fem's scenes: the press (and release), and with the full run the
// pull too.
std::vector<Row> fem_rows(const Context& c) {
  std::vector<Row> rows = fem_rows(c, kPressLoad);
  if (!c.quick)
    for (Row& r : fem_rows(c, kPullLoad)) rows.push_back(std::move(r));
  return rows;
}

std::vector<Row> adaptive_rows(const Context& c) {
  std::vector<Row> rows;
  struct Case {
    double k, dt;
    int steps;
  };
  const std::vector<double> thresholds =
      c.quick ? std::vector<double>{1e-8, 1e-12, 1e-16} : std::vector<double>{1e-6, 1e-8, 1e-10, 1e-12, 1e-14, 1e-16};
  for (const ms::Integrator integrator :
       {ms::Integrator::symplectic_euler, ms::Integrator::velocity_verlet, ms::Integrator::rk4,
        ms::Integrator::implicit_euler, ms::Integrator::local_global})
    for (const Case cs : {Case{50, 1.0 / 30, 6}, Case{5000, 5e-4, 400}}) {
      progress(std::string("massspring adaptive: ") + ms::name(integrator) + ", k " + fmt(cs.k) + ", dt " + fmt(cs.dt));
      ms::Material m;
      m.mass = 1e-3, m.k = cs.k, m.b = 0.02, m.drag = 0.002;
      ms::Lattice l = ms::make_box(12, 12, 12, 0.01, m);
      ms::anchor_where(l, [](const Eigen::Vector3d& p) { return p.z() < 1e-9; });
      const int contact = 6 + 12 * (6 + 12 * 11);
      ms::Options o;
      o.integrator = integrator;
      o.dt = cs.dt;
      // Runs the press; returns wall ms and the most masses simulated.
      auto press = [&](ms::Simulator& sim, ms::State& st, int* simulated) {
        const auto t0 = std::chrono::steady_clock::now();
        for (int k = 0; k < cs.steps; ++k)
          *simulated = std::max(*simulated, sim.step(st, {{contact, Eigen::Vector3d(0, 0, -0.3)}}).simulated);
        return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
      };
      ms::Simulator full(l, o);
      ms::State ref = ms::rest_state(l);
      int all = 0;
      const double full_ms = press(full, ref, &all);
      for (const double threshold : thresholds) {
        o.threshold = threshold;
        ms::Simulator adaptive(l, o);
        ms::State st = ms::rest_state(l);
        int simulated = 0;
        const double run_ms = press(adaptive, st, &simulated);
        rows.push_back({"adaptive",
                        {{"integrator", std::string(ms::name(integrator))},
                         {"k", cs.k},
                         {"dt", cs.dt},
                         {"substeps", double(full.substeps())},
                         {"threshold", threshold}},
                        {{"rel_error", (st.x - ref.x).norm() / (ref.x - l.rest).norm()},
                         {"simulated_fraction", double(simulated) / double(all)},
                         {"ms", run_ms},
                         {"full_ms", full_ms}}});
      }
    }
  return rows;
}

std::vector<Row> massspring_rows(const Context& c) {
  std::vector<Scene> scenes;
  if (c.quick) {
    scenes.push_back(box(6));
    scenes.push_back(dome(8, 16));
  } else {
    scenes.push_back(box(10));
    scenes.push_back(dome(64, 64));
    scenes.push_back(box(22));
    scenes.push_back(box(46));
  }
  std::vector<Row> all;
  for (const Scene& sc : scenes)
    for (Row& r : scene_rows(sc, c)) all.push_back(std::move(r));
  for (Row& r : recovery_rows(c)) all.push_back(std::move(r));
  for (Row& r : adaptive_rows(c)) all.push_back(std::move(r));
  for (Row& r : fem_rows(c)) all.push_back(std::move(r));
  return all;
}

}  // namespace

Suite massspring_suite() {
  Suite s{"massspring",
          "mass-spring behavior model: integrators, adaptive active masses and MuJoCo 2.2.2 on the same lattices, "
          "ms per simulated s against error from a converged RK4 reference and from a converged corotational FEM "
          "of the solid the lattice stands for; the elastic surfaces' recovery after release",
          massspring_rows};
  s.tables = {{"reference",
               "The reference each lattice's errors are measured from: RK4 at a sixteenth of its stable step; "
               "ref_self_error is its change when that step is halved, below which two errors count as equal."},
              {"step",
               "A lattice pressed at one mass for 0.1 s then released, 0.2 s simulated: wall ms per simulated s "
               "(median of 3 runs, one run when a run takes over 2 s) against the positions' relative error from the "
               "reference, per integrator, step and adaptive threshold (simulated_fraction: masses simulated), and "
               "MuJoCo on the same lattice; speedup_at_equal_error is MuJoCo's time over our fastest row with no "
               "larger error, in the same run."},
              {"recovery",
               "Seed 000's elastic surfaces as the default scene builds them (4 cm sheet, 2 cm dome), with their "
               "bending hinges and without (membrane), pressed 7 mm over 0.2 s, held 0.5 s and let go: the largest "
               "vertex distance from rest 1 s and 2 s after the release, the touch's wall time per 1 kHz servo tick "
               "while pressed, and the force felt at the end of the hold."},
              {"adaptive",
               "The adaptive model against the full one with the same integrator and step as the threshold (J) "
               "falls: a 12^3 box with its floor anchored, pressed with 0.3 N at its top for 0.2 s, at 1/30 s "
               "(the explicit integrators' substeps in `substeps`) and at 0.5 ms with 5000 N/m springs; rel_error "
               "of the final positions, the most masses simulated at once as a fraction of the full model's, and "
               "wall ms against the full model's (full_ms)."},
              {"fem_reference",
               "The continuum reference of `against_fem`: the corotational FEM (models/fem) of the solid the cube's "
               "lattice stands for (Young's modulus 2.5 k / a, Poisson's ratio 1/4), its mesh refined `refinement` "
               "times, trapezoidal rule at 0.1 ms; its relative change with one refinement less (ref_space_error) "
               "and twice the step (ref_time_error), its settled press's change with one refinement less "
               "(ref_static_error), and its wall ms per simulated s."},
              {"against_fem_static",
               "The same load settled (quasi-static): the positions' relative error from the reference's settled "
               "load at the masses, for the springs and for the FEM on the lattice's own nodes, per `scene`."},
              {"against_fem",
               "A 4 cm cube of 5^3 masses (springs along the edges and both face diagonals, floor anchored), its "
               "top's centre 2 x 2 cm patch pressed (`scene` press) or, without --quick, also pulled up (pull) "
               "with 0.2 N for 0.1 s then let go, 0.2 s simulated: the "
               "positions' relative error from the FEM reference at the masses, every 20 ms, per behavior model "
               "(`springs`: the mass-spring lattice; `fem`: the FEM on the lattice's own nodes; `modal`: that FEM's "
               "lowest `modes` vibration modes, linearised at rest and stepped exactly; `bullet`: Bullet "
               "3.24's btSoftBody with a link along every tetrahedron edge, over its stiffness coefficient kLST and "
               "position iterations), integrator, step and adaptive threshold, against wall ms per simulated s "
               "(median of 3 runs); a Bullet row's speedup_at_equal_error is its time over our fastest row with no "
               "larger error (0: none of ours is as close)."}};
  s.plots = {{"step",
              "ms_per_sim_s",
              "rel_error",
              "wall ms per simulated s",
              "relative error",
              {"integrator", "mujoco_integrator", "threshold"},
              {"lattice"},
              {"integrator", "mujoco"}}};
  s.goals = {{"every MuJoCo row matched at equal or lower error by one of ours at least 20 times faster, on the "
              "largest lattice both run",
              "step", "speedup_at_equal_error", 20, "lattice", "dome4097", true},
             {"elastic surfaces back within 0.1 mm of rest (every vertex) within 2 s of release", "recovery",
              "off_2s_mm", 0.1, "model", "hinges"},
             {"adaptive error under 1 % at the smallest threshold, every integrator, with substeps and implicit "
              "steps",
              "adaptive", "rel_error", 0.01, "threshold", "1e-16"},
             {"at equal or lower error against the FEM reference, the fastest of ours at least 10 times faster than "
              "Bullet's soft body",
              "against_fem", "speedup_at_equal_error", 10, "model", "bullet", true},
             {"FEM reference converged: its settled press under 5 % change with one refinement less", "fem_reference",
              "ref_static_error", 0.05}};
  return s;
}

}  // namespace hcosim::services::bench
