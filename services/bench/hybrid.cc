// bench hybrid: the hybrid deformable model of seed 001, per part and whole.
//
// schain_tick: the S-Chain haptic tick alone, pressing the top of a 10 cm
//   cube of `elements` chains `depth` deep (a 200-tick ramp, then 300 ticks
//   held); `moved` is the largest number of moved chains.
// pipeline: the whole model as the service runs it: haptic tick, behavior
//   step (1 kHz), and a visual frame every 33 ticks (fill_mesh: map,
//   normals and the DeformedMesh's floats),
//   over a press, hold and release. `seed` is 001 Fig 7's scale, `100x` a
//   hundred times more chains, masses and visual vertices (trilinear map:
//   dense mean value weights of that size do not fit in memory; the seed
//   scale's force gain), `organ`
//   the default scene's liver (deploy/meshes/liver.obj).
// against_fem: the seed's cube's behavior models (springs, FEM, modal) pressed and
//   released (and, full run, pulled), against the FEM of its tissue refined
//   2 (--quick) or 3 times: the displacement error over time.
// seen_vs_felt: the default scene's cube and organ pressed from above 4 mm
//   past their drawn surface at a few points: how much of the stylus tip's
//   depth the drawn surface followed, and the force felt against the
//   behavior model's for that press; let go, the work the stylus got back
//   over the work it did, and the force at contact's end over its peak.
// stiffening: at the same points, the behavior model's force for a 4 mm
//   press of its drawn surface over 40 times its force for 0.1 mm, and the
//   same at the force gain's points: why some points sink less; along the
//   organ's line, the largest ratio between two points 2 mm apart
//   (`neighbours`): how local the differences are.
// visual_map: each map on a known smooth deformation (a press dent and a
//   bend) applied to the cage, for the rounded box (`shape` box: 602 and
//   5402 vertices) and an organ-like smooth ellipsoid inscribed in the cube
//   (`shape` organ: 3752 vertices, 7500 triangles, 001 Fig 9's size):
//   rel_error is the RMS distance of the mapped
//   visual vertices from the deformation's own values over the RMS
//   displacement; ms is the whole map, ratio to trilinear in the same run.
// force_vs_behavior: the force felt against the behavior model's static
//   force for a press of its drawn surface (behavior_surface_force) as
//   deep, 0.5 to 25 mm, at each side's gain point of a 10 cm cube with a
//   stiff side: the largest relative difference, and the largest ratio of
//   the S-Chain alone to the behavior model.
// press: the behavior model's static force at the top centre every
//   `step_mm` down to half the cube's size, with its volume floors and
//   without (volume 0): how deep it rises at every step before the first
//   drop (a snap-through), and the force there.
#include <algorithm>
#include <chrono>

#include "adapters/deformable/mesh_idl.h"
#include "models/deformable/hybrid.h"
#include "models/deformable/surface.h"
#include "services/bench/bench.h"

namespace hcosim::services::bench {
namespace {

using namespace hcosim::models::deformable;
using Clock = std::chrono::steady_clock;

double us_since(Clock::time_point t) { return std::chrono::duration<double, std::micro>(Clock::now() - t).count(); }

double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::size_t(q * double(v.size() - 1) + 0.5)];
}

int top_centre(int n) { return n / 2 + n * (n / 2 + n * (n - 1)); }

Row schain_row(int n, double depth) {
  HybridSpec s;
  s.elements = n;
  SChain chain(hybrid_chains(s), s.relax_rate, s.limit_stiffness);
  const int e = top_centre(n);
  const Eigen::Vector3d rest = chain.lattice().rest(e);
  std::vector<double> t;
  std::size_t moved = 0;
  for (int k = 0; k < 500; ++k) {
    const Eigen::Vector3d hip = rest - Eigen::Vector3d(0, 0, depth * std::min(1.0, (k + 1) / 200.0));
    const auto t0 = Clock::now();
    chain.tick(1e-3, e, hip);
    t.push_back(us_since(t0));
    moved = std::max(moved, chain.moved().size());
  }
  return {"schain_tick",
          {{"elements", double(n * n * n)}, {"depth_mm", depth * 1e3}},
          {{"moved", double(moved)}, {"p50_us", quantile(t, 0.5)}, {"p99_us", quantile(t, 0.99)}}};
}

// The default scene's organ (deploy/default.yaml): the liver, 4.5 cm long,
// 16 nodes along it, its +x lobe four times stiffer, on the floor.
HybridSpec organ_spec() {
  HybridSpec s;
  s.shape = models::massspring::read_obj(HCOSIM_LIVER_OBJ);
  s.size = 0.045, s.elements = 16, s.stiff_ratio = 4;
  s.centre = Eigen::Vector3d(0, 0, 0.0075);
  return s;
}

Row pipeline_row(const std::string& scale, BehaviorModel model) {
  HybridSpec s = scale == "organ" ? organ_spec() : HybridSpec{};
  if (scale == "100x") s.elements = 46, s.visual_subdivisions = 300, s.map = VisualMap::trilinear;
  s.behavior_model = model;
  // At 100x the force gain is the seed scale's: computing its own settles
  // 97,336 masses at 21 depths, over 20 minutes here, and the gain only
  // scales the force, not what a tick costs.
  GainSource gain;
  if (scale == "100x")
    gain = [](const HybridSpec& big, const Weights&) {
      HybridSpec seed = big;
      seed.elements = HybridSpec{}.elements;
      return force_gain(seed);
    };
  const auto b0 = Clock::now();
  Hybrid h(s, {}, gain);
  const double build_ms = us_since(b0) * 1e-3;
  const Eigen::Vector3d top(s.centre.x() + 0.002, s.centre.y() + 0.001, rest_box(s).max().z());
  std::vector<double> haptic, behavior, visual;
  int substeps = 0;
  DeformedMesh mesh;
  for (int k = 0; k < 1500; ++k) {
    // 8 mm in over 0.5 s, held 0.5 s, out over 0.25 s, then free.
    const double d = k < 500 ? 0.008 * k / 500 : k < 1000 ? 0.008 : std::max(0.0, 0.008 * (1 - (k - 1000) / 250.0));
    const auto t0 = Clock::now();
    h.touch(1e-3, top - Eigen::Vector3d(0, 0, d - 1e-4), false);
    haptic.push_back(us_since(t0));
    const auto t1 = Clock::now();
    h.advance();
    behavior.push_back(us_since(t1));
    substeps = std::max(substeps, h.substeps());
    if (k % 33 == 0) {
      // What the service's visual worker does, short of writing the sample.
      const auto t2 = Clock::now();
      adapters::deformable::fill_mesh(mesh, "cube", StepStamp(), h.surface(), h.triangles());
      visual.push_back(us_since(t2) * 1e-3);
      if (!std::all_of(mesh.positions().begin(), mesh.positions().end(), [](float f) { return std::isfinite(f); }))
        throw std::runtime_error("bench hybrid: non-finite visual mesh");
    }
  }
  return {"pipeline",
          {{"scale", scale},
           {"behavior", std::string(name(model))},
           {"chains", double(h.haptic().lattice().size())},
           {"masses", double(h.behavior().lattice().size())},
           {"springs", double(h.behavior().lattice().springs.size())},
           {"visual_vertices", double(h.visual_rest().vertices.cols())},
           {"map", std::string(name(s.map))}},
          {{"haptic_p50_us", quantile(haptic, 0.5)},
           {"haptic_p99_us", quantile(haptic, 0.99)},
           {"behavior_p50_us", quantile(behavior, 0.5)},
           {"behavior_p99_us", quantile(behavior, 0.99)},
           {"behavior_substeps_most", double(substeps)},
           {"behavior_substeps_bound", model != BehaviorModel::springs ? 1.0 : double(h.behavior().substeps())},
           {"visual_frame_ms", quantile(visual, 0.5)},
           {"visual_frame_p99_ms", quantile(visual, 0.99)},
           {"build_ms", build_ms}}};
}

// What is seen against what is felt: pressed from above at each point
// (offsets from the centre, m) from 1 mm over the drawn surface to 4 mm
// past it over 0.3 s and held 1.2 s, how much of the stylus tip's depth
// inside the object at rest the drawn surface has followed (1: the surface
// follows the tip; less: the tip is drawn inside the object; more: the
// surface sinks past it), and how far the force felt along the stylus's
// press (from the proxy to the HIP) is from the behavior model's static
// force for that press of its drawn surface (behavior_surface_force along
// it), and the normal force felt from its force for a press along the
// normal as deep; then let go over 0.3 s, the work the stylus
// got back over the work it did, and the force at the last tick of
// contact over the contact's largest.
Row seen_row(const std::string& body, const HybridSpec& s, const std::vector<Eigen::Vector2d>& points) {
  std::vector<double> ratio, felt, normal, returned, end;
  for (const Eigen::Vector2d& p : points) {
    Hybrid h(s);
    const Eigen::Vector2d at = s.centre.head<2>() + p;
    const double top = height_over(h.visual_rest().vertices, h.triangles(), at);
    const Eigen::Vector3d above(at.x(), at.y(), top + 0.001), tip = above - Eigen::Vector3d(0, 0, 0.005);
    double in = 0, out = 0, peak = 0, last = 0;
    Eigen::Vector3d from = above;
    for (int k = 0; k < 2000; ++k) {
      const double d = 0.005 * std::min({1.0, (k + 1) / 300.0, std::max(0.0, (1800 - k) / 300.0)});
      const Eigen::Vector3d hip = above - Eigen::Vector3d(0, 0, d);
      const Touch t = h.touch(1e-3, hip, false);
      h.advance();
      const double work = -t.force.dot(hip - from);
      if (work > 0)
        in += work;
      else
        out -= work;
      if (t.in_contact) last = t.force.norm(), peak = std::max(peak, last);
      from = hip;
      if (k == 1499) {
        if (!t.in_contact) throw std::runtime_error("bench hybrid: the " + body + " was not touched");
        ratio.push_back(1 - depth_inside(h.surface(), h.triangles(), tip) /
                                depth_inside(h.visual_rest().vertices, h.triangles(), tip));
        const Eigen::Vector3d press = hip - h.proxy();
        felt.push_back(std::abs(
            -t.force.dot(press.normalized()) / behavior_surface_force(s, h.proxy(), {press.norm()}, press)[0] - 1));
        normal.push_back(std::abs(t.force.dot(t.normal) / behavior_surface_force(s, h.proxy(), {t.depth})[0] - 1));
      }
    }
    returned.push_back(out / in);
    end.push_back(last / peak);
  }
  return {"seen_vs_felt",
          {{"body", body}, {"points", double(points.size())}},
          {{"min_ratio", *std::min_element(ratio.begin(), ratio.end())},
           {"median_ratio", quantile(ratio, 0.5)},
           {"max_ratio", *std::max_element(ratio.begin(), ratio.end())},
           {"felt_rel_error", *std::max_element(felt.begin(), felt.end())},
           {"felt_rel_error_normal", *std::max_element(normal.begin(), normal.end())},
           {"work_returned_max", *std::max_element(returned.begin(), returned.end())},
           {"end_force_max", *std::max_element(end.begin(), end.end())}}};
}

// How much the behavior model stiffens under a 4 mm press of its drawn
// surface at each of the same points (behavior_surface_force: the force
// for 4 mm over 40 times the force for 0.1 mm; 1 if it were linear), and
// at the force gain's points. The force felt is the gain point's for the
// depth times the compliance at rest there over here, so a point that
// stiffens more than the gain point sinks by less than the stylus's depth,
// and one that stiffens less by more. `line`: where in `points` a line of
// points begins, each the next's neighbour (none: -1).
Row stiffening_row(const std::string& body, const HybridSpec& s, const std::vector<Eigen::Vector2d>& points,
                   int line = -1) {
  const Hybrid h(s);
  const auto stiffening = [](double shallow, double deep) { return (deep / 4e-3) / (shallow / 1e-4); };
  std::vector<double> at_points;
  for (const Eigen::Vector2d& p : points) {
    const Eigen::Vector2d at = s.centre.head<2>() + p;
    const double top = height_over(h.visual_rest().vertices, h.triangles(), at);
    const std::vector<double> f = behavior_surface_force(s, Eigen::Vector3d(at.x(), at.y(), top), {1e-4, 4e-3});
    at_points.push_back(stiffening(f[0], f[1]));
  }
  const ForceGain& g = h.gain();
  Row r{"stiffening",
        {{"body", body}, {"points", double(points.size())}},
        {{"min", *std::min_element(at_points.begin(), at_points.end())},
         {"median", quantile(at_points, 0.5)},
         {"max", *std::max_element(at_points.begin(), at_points.end())},
         {"gain_soft", stiffening(g.at(1e-4, false), g.at(4e-3, false))}}};
  if (!g.stiff.empty()) r.metrics.push_back({"gain_stiff", stiffening(g.at(1e-4, true), g.at(4e-3, true))});
  if (line >= 0) {
    double most = 1;
    for (std::size_t k = std::size_t(line) + 1; k < at_points.size(); ++k)
      most = std::max(most, std::max(at_points[k], at_points[k - 1]) / std::min(at_points[k], at_points[k - 1]));
    r.metrics.push_back({"neighbours", most});
  }
  return r;
}

// The hybrid cube's behavior models against a continuum:
// the default 10 cm cube, its floor anchored, pressed (sign -1) or pulled
// (+1) with 0.5 N on a patch two cells wide at its top centre for 0.2 s,
// then let go, to 0.4 s; its nodes sampled every 20 ms. The reference is
// the FEM of the cube's tissue (HybridSpec::fem, 10 kPa) refined 2 times
// (--quick) or 3, trapezoidal at 1 ms, read at the lattice's nodes.
constexpr double kFemPatchN = 0.5, kFemPress = 0.2, kFemEnd = 0.4, kFemSample = 0.02;

// The patch's load on a cube's top nodes (rest, m, its corner at the
// origin or anywhere: only the top and the middle matter): a bilinear tent
// one lattice cell (`cell`, m) wide about the top's centre, so that the
// lattice and a refined mesh take the same resultant at the same place.
std::vector<models::massspring::PointForce> patch(const Eigen::Matrix3Xd& rest, double cell, double sign) {
  const Eigen::Vector3d lo = rest.rowwise().minCoeff(), hi = rest.rowwise().maxCoeff(), mid = 0.5 * (lo + hi);
  std::vector<models::massspring::PointForce> out;
  double sum = 0;
  for (int i = 0; i < rest.cols(); ++i) {
    if (rest(2, i) < hi.z() - 1e-9) continue;
    const double w = std::max(0.0, 1 - std::abs(rest(0, i) - mid.x()) / cell) *
                     std::max(0.0, 1 - std::abs(rest(1, i) - mid.y()) / cell);
    if (w > 0) out.push_back({i, Eigen::Vector3d(0, 0, w)}), sum += w;
  }
  for (models::massspring::PointForce& f : out) f.force *= sign * kFemPatchN / sum;
  return out;
}

// Samples at the lattice's nodes over the scene, and the wall time of the steps.
struct FemTrace {
  std::vector<Eigen::Matrix3Xd> samples;
  double wall_s = 0;
};

template <class Step, class Sample>
FemTrace scene_trace(double dt, Step&& step, Sample&& sample) {
  FemTrace t;
  const int steps = int(std::lround(kFemEnd / dt)), every = int(std::lround(kFemSample / dt));
  for (int k = 0; k < steps; ++k) {
    const auto t0 = Clock::now();
    step(k * dt < kFemPress - 1e-12);
    t.wall_s += us_since(t0) * 1e-6;
    if ((k + 1) % every == 0) t.samples.push_back(sample());
  }
  return t;
}

// The cube's FEM refined r times (r = 1: on the hybrid's own nodes).
FemTrace fem_cube(const HybridSpec& s, int r, models::fem::Scheme scheme, double sign) {
  const int cells = s.elements - 1, n = cells * r + 1;
  models::fem::Mesh m = models::fem::box_mesh(n, n, n, s.size / (n - 1));
  for (int i = 0; i < m.size(); ++i) m.anchored[i] = i < n * n;
  models::fem::Options o;
  o.dt = 1e-3, o.scheme = scheme;
  models::fem::Corotational f(m, s.fem, o);
  models::massspring::State st = models::fem::rest_state(m);
  const std::vector<models::massspring::PointForce> load = patch(m.rest, s.size / cells, sign), none;
  const int e = s.elements;
  return scene_trace(
      o.dt, [&](bool loaded) { f.step(st, loaded ? load : none); },
      [&] {
        Eigen::Matrix3Xd x(3, e * e * e);
        for (int k = 0; k < e; ++k)
          for (int j = 0; j < e; ++j)
            for (int i = 0; i < e; ++i) x.col(i + e * (j + e * k)) = st.x.col(r * i + n * (r * j + n * r * k));
        x.colwise() -= Eigen::Vector3d::Constant(0.5 * s.size) - s.centre;
        return x;
      });
}

// RMS distance from the reference over its RMS displacement from rest.
double against(const FemTrace& got, const FemTrace& ref, const Eigen::Matrix3Xd& rest) {
  double num = 0, den = 0;
  for (std::size_t k = 0; k < ref.samples.size(); ++k)
    num += (got.samples[k] - ref.samples[k]).squaredNorm(), den += (ref.samples[k] - rest).squaredNorm();
  return std::sqrt(num / den);
}

std::vector<Row> against_fem_rows(bool quick) {
  HybridSpec s;  // the seed's cube, its tissue 10 kPa
  const models::massspring::Lattice lat = hybrid_masses(s);
  std::vector<Row> rows;
  for (const double sign : quick ? std::vector<double>{-1} : std::vector<double>{-1, 1}) {
    const std::string scene = sign < 0 ? "press" : "pull";
    const int r = quick ? 2 : 3;
    progress("hybrid against the FEM, " + scene + ": the reference, refined " + std::to_string(r) + " times");
    const FemTrace ref = fem_cube(s, r, models::fem::Scheme::trapezoidal, sign);
    auto add = [&](const std::string& model, const std::string& how, const FemTrace& t) {
      rows.push_back({"against_fem",
                      {{"model", model}, {"integrator", how}, {"scene", scene}, {"refinement", double(r)}},
                      {{"rel_error", against(t, ref, lat.rest)}, {"ms_per_sim_s", t.wall_s * 1e3 / kFemEnd}}});
    };
    progress("hybrid against the FEM, " + scene + ": the reference refined once less, and the FEM behavior model");
    add("fem_reference_coarser", "trapezoidal", fem_cube(s, r - 1, models::fem::Scheme::trapezoidal, sign));
    add("fem", "implicit_euler", fem_cube(s, 1, models::fem::Scheme::implicit_euler, sign));
    progress("hybrid against the FEM, " + scene + ": the springs");
    models::massspring::Simulator sim(lat, s.behavior);
    models::massspring::State st = models::massspring::rest_state(lat);
    const std::vector<models::massspring::PointForce> load = patch(lat.rest, s.size / (s.elements - 1), sign), none;
    add("springs", models::massspring::name(s.behavior.integrator),
        scene_trace(
            s.behavior.dt, [&](bool loaded) { sim.step(st, loaded ? load : none); }, [&] { return st.x; }));
    progress("hybrid against the FEM, " + scene + ": the modal behavior model");
    const models::fem::Corotational linear(hybrid_mesh(s), s.fem, {});
    for (const int modes : {s.modes, 4 * s.modes}) {
      const models::fem::Modal modal(linear, models::fem::ModalOptions{s.behavior.dt, modes});
      models::massspring::State ms = models::fem::rest_state(linear.mesh());
      add("modal", "exact",
          scene_trace(
              s.behavior.dt, [&](bool loaded) { modal.step(ms, loaded ? load : none); }, [&] { return ms.x; }));
      rows.back().params.push_back({"modes", double(modes)});
    }
  }
  return rows;
}

// A press dent at the top centre and a bend, both smooth (m, world).
Eigen::Vector3d deform(const HybridSpec& s, const Eigen::Vector3d& p) {
  const Eigen::Vector3d q = (p - s.centre) / s.size;
  const double h = q.z() + 0.5;
  const double dent = -0.08 * s.size * std::exp(-(q.x() * q.x() + q.y() * q.y()) / 0.04) * h * h;
  return p + Eigen::Vector3d(0.03 * s.size * h * h, 0, dent);
}

std::vector<Row> visual_rows(bool quick) {
  std::vector<Row> rows;
  struct Shape {
    const char* name;
    int subdivisions;
    double exponent;
  };
  const std::vector<Shape> shapes =
      quick ? std::vector<Shape>{{"box", 10, 8}} : std::vector<Shape>{{"box", 10, 8}, {"box", 30, 8}, {"organ", 25, 2}};
  for (const Shape& shape : shapes) {
    double trilinear_ms = 0;
    for (VisualMap m : {VisualMap::trilinear, VisualMap::mvc, VisualMap::mvc_sparse}) {
      HybridSpec s;
      s.map = m;
      s.visual_subdivisions = shape.subdivisions;
      s.visual_exponent = shape.exponent;
      const Hybrid h(s);
      const models::massspring::Lattice& lat = h.behavior().lattice();
      const std::vector<int>& cage = h.cage_masses();
      Eigen::Matrix3Xd x(3, cage.size());
      for (std::size_t i = 0; i < cage.size(); ++i) x.col(i) = deform(s, lat.rest.col(cage[i]));
      std::vector<double> ms;
      Eigen::Matrix3Xd got;
      for (int r = 0; r < 21; ++r) {
        const auto t0 = Clock::now();
        got = apply(h.map(), x);
        ms.push_back(us_since(t0) * 1e-3);
      }
      const Eigen::Matrix3Xd& v = h.visual_rest().vertices;
      double err = 0, disp = 0;
      for (int i = 0; i < v.cols(); ++i) {
        const Eigen::Vector3d f = deform(s, v.col(i));
        err += (got.col(i) - f).squaredNorm(), disp += (f - v.col(i)).squaredNorm();
      }
      const double median = quantile(ms, 0.5);
      if (m == VisualMap::trilinear) trilinear_ms = median;
      rows.push_back(
          {"visual_map",
           {{"method", std::string(name(m))}, {"shape", std::string(shape.name)}, {"vertices", double(v.cols())}},
           {{"ms", median},
            {"ms_ratio_to_trilinear", median / trilinear_ms},
            {"rel_error", std::sqrt(err / disp)},
            {"weights", double(h.map().nonZeros())}}});
    }
  }
  return rows;
}

// The force felt against the behavior model's for a press of the surface
// drawn, on each side of the 10 cm cube with a stiff side 4 times
// stiffer, at its gain point (models/deformable/force_gain.h, ForceGain):
// pressed from 1 mm above to each depth over 0.1 s and held 0.9 s (the
// force follows the behavior model, which rings for a few tenths of a
// second under a deep press of the stiff side), let go for 1 s between
// presses.
std::vector<Row> force_rows() {
  HybridSpec s;
  s.map = VisualMap::trilinear, s.stiff_ratio = 4;
  std::vector<double> depths;
  for (const double mm : {0.5, 1.0, 2.0, 3.5, 5.0, 7.0, 9.0, 11.0, 13.0, 15.0, 17.0, 19.0, 21.0, 23.0, 25.0})
    depths.push_back(mm * 1e-3);
  std::vector<Row> rows;
  for (const bool stiff : {false, true}) {
    Hybrid h(s);
    const Eigen::Vector3d r = h.gain_point(stiff);
    double z = r.z() + 0.001;
    while (!h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), z), false).in_contact) h.advance(), z -= 1e-5;
    const double surface = h.proxy().z();
    const std::vector<double> behavior = behavior_surface_force(s, h.proxy(), depths);
    double felt = 0, alone = 0;
    for (std::size_t j = 0; j < depths.size(); ++j) {
      for (int k = 0; k < 1000; ++k) h.touch(1e-3, Eigen::Vector3d(r.x(), r.y(), surface + 0.002), false), h.advance();
      Touch t;
      for (int k = 0; k < 1000; ++k) {
        t = h.touch(
            1e-3, Eigen::Vector3d(r.x(), r.y(), surface + 0.001 - (0.001 + depths[j]) * std::min(1.0, (k + 1) / 100.0)),
            false);
        h.advance();
      }
      felt = std::max(felt, std::abs(t.force.z() / behavior[j] - 1));
      alone = std::max(alone, h.haptic().force().z() / behavior[j]);
    }
    rows.push_back({"force_vs_behavior",
                    {{"side", std::string(stiff ? "stiff" : "soft")}, {"depth_mm", std::string("0.5..25")}},
                    {{"rel_error", felt}, {"chain_alone_max_ratio", alone}}});
  }
  return rows;
}

Row press_row(BehaviorModel model, double volume, double step) {
  HybridSpec s;
  s.map = VisualMap::trilinear;
  s.volume = volume;
  s.behavior_model = model;
  const int e = top_centre(s.elements);
  const double half = 0.5 * s.size;
  double last = 0, rises_to = half, peak = 0, snap_from = 0, snap_to = 0;
  std::vector<double> ms;
  for (double depth = step; depth <= half + 1e-9; depth += step) {
    const auto t0 = Clock::now();
    const double f = behavior_static_force(s, e, Eigen::Vector3d(0, 0, -depth)).z();
    ms.push_back(us_since(t0) * 1e-3);
    if (f <= last && rises_to == half) rises_to = depth - step, snap_from = last, snap_to = f;
    if (rises_to == half) peak = f;
    last = f;
  }
  Row row{"press",
          {{"behavior", std::string(name(model))}, {"step_mm", step * 1e3}},
          {{"rises_to_mm", rises_to * 1e3},
           {"force_there_n", peak},
           {"drop_from_n", snap_from},
           {"drop_to_n", snap_to},
           {"ms_per_press", quantile(ms, 0.5)}}};
  if (model == BehaviorModel::springs) {
    const models::massspring::Simulator behavior(hybrid_masses(s), s.behavior);
    row.params.push_back({"floors", std::string(volume > 0 ? "on" : "off")});
    row.params.push_back({"volume", volume});
    row.metrics.push_back({"omega_max", behavior.spectrum().omega_max});
    row.metrics.push_back({"behavior_substeps", double(behavior.substeps())});
  }
  return row;
}

std::vector<Row> hybrid_rows(const Context& c) {
  std::vector<Row> rows;
  const std::vector<int> sizes = c.quick ? std::vector<int>{10, 22} : std::vector<int>{10, 22, 46};
  for (const int n : sizes)
    for (const double depth : {0.004, 0.012, 0.03}) {
      progress("hybrid schain_tick: " + std::to_string(n * n * n) + " elements, " + std::to_string(int(depth * 1e3)) +
               " mm");
      rows.push_back(schain_row(n, depth));
    }
  for (const std::string& scale :
       c.quick ? std::vector<std::string>{"seed"} : std::vector<std::string>{"seed", "100x"}) {
    progress("hybrid pipeline at " + scale + " scale (building the map)");
    rows.push_back(pipeline_row(scale, BehaviorModel::springs));
  }
  progress("hybrid pipeline on the default scene's organ (building the map)");
  rows.push_back(pipeline_row("organ", BehaviorModel::springs));
  progress("hybrid pipeline at seed scale, the FEM as the behavior model");
  rows.push_back(pipeline_row("seed", BehaviorModel::fem));
  progress("hybrid pipeline at seed scale, the FEM's lowest modes as the behavior model");
  rows.push_back(pipeline_row("seed", BehaviorModel::modal));
  progress("hybrid surface seen against depth felt, the default scene's cube and organ");
  {
    HybridSpec cube;  // deploy/default.yaml's
    cube.size = 0.03, cube.centre = Eigen::Vector3d(0, 0, 0.015);
    const double q = 0.25 * cube.size;
    const std::vector<Eigen::Vector2d> square = {{0, 0}, {q, 0}, {-q, q}, {0, -q}};
    rows.push_back(seen_row("cube", cube, square));
    rows.push_back(stiffening_row("cube", cube, square));
    // The organ every 2 mm along its length, from its soft right lobe
    // across the middle to its stiff left lobe, and off that line.
    std::vector<Eigen::Vector2d> line = {{-0.006, 0.004}, {0.006, 0.004}};
    for (int k = -8; k <= 8; ++k) line.push_back({0.002 * k, -0.002});
    rows.push_back(seen_row("organ", organ_spec(), line));
    rows.push_back(stiffening_row("organ", organ_spec(), line, 2));
  }
  for (Row& r : against_fem_rows(c.quick)) rows.push_back(std::move(r));
  progress("hybrid visual maps on a known deformation");
  for (Row& r : visual_rows(c.quick)) rows.push_back(std::move(r));
  progress("hybrid S-Chain force against the behavior model's static force");
  for (Row& r : force_rows()) rows.push_back(std::move(r));
  for (const double volume : {HybridSpec{}.volume, 0.0}) {
    progress(std::string("hybrid behavior model pressed to half its size, volume floors ") +
             (volume > 0 ? "on" : "off"));
    rows.push_back(press_row(BehaviorModel::springs, volume, c.quick ? 0.005 : 0.002));
  }
  progress("hybrid behavior model pressed to half its size, the corotational FEM");
  rows.push_back(press_row(BehaviorModel::fem, 0, c.quick ? 0.005 : 0.002));
  return rows;
}

}  // namespace

Suite hybrid_suite() {
  Suite s{"hybrid",
          "hybrid deformable model (seed 001): S-Chain tick, whole pipeline at seed and 100x scale, visual maps' "
          "error and time, S-Chain force against the behavior model",
          hybrid_rows};
  s.tables = {
      {"schain_tick",
       "The S-Chain haptic tick alone (001's force model) pressing the top of a 10 cm cube of `elements` chains "
       "`depth_mm` deep: a 200-tick ramp then 300 ticks held; p50 and p99 over every tick, `moved` the most chains "
       "moved at once."},
      {"pipeline",
       "The whole model as the service runs it over a press, hold and release: haptic tick and behavior step at "
       "1 kHz, a visual frame every 33 ticks; `seed` is 001 Fig 7's scale, `100x` a hundred times more (trilinear "
       "map: dense mean value weights of that size do not fit in memory), `organ` the default scene's liver "
       "(deploy/meshes/liver.obj, 4.5 cm, 16 nodes along it); build_ms includes the map's weights; "
       "behavior_substeps_most is the most substeps one behavior step took (its volume floors count only "
       "while pressed near them), behavior_substeps_bound what every step would take with all of them counted; "
       "`behavior` fem: the corotational FEM (10 kPa) as the behavior model, stepped by implicit Euler at 1 kHz; "
       "modal: its 32 lowest modes about rest, each stepped exactly at 1 kHz (build_ms includes the eigensolve)."},
      {"visual_map",
       "Each visual map on a known smooth deformation (a press dent and a bend) of the cage: time for the whole "
       "map (median) against the RMS distance of mapped vertices from the deformation's own, over the RMS "
       "displacement; trilinear is the baseline in the same run."},
      {"against_fem",
       "The hybrid cube's behavior models against a continuum: the seed's 10 cm cube, floor "
       "anchored, pressed (`scene` press) or pulled (pull, full run only) with 0.5 N on a patch two cells wide (a "
       "bilinear tent) at its top centre for 0.2 s, then let go, to 0.4 s; rel_error is the RMS distance of its 1000 "
       "nodes from the "
       "reference's, sampled every 20 ms, over the reference's RMS displacement. The reference is the FEM of the "
       "tissue the cube stands for (`HybridSpec::fem`: 10 kPa, Poisson 0.3, 1000 kg/m^3, mass damping 10/s) refined "
       "`refinement` times (2 with --quick: 6859 nodes; 3: 21952), trapezoidal at 1 ms; `fem_reference_coarser` is "
       "that FEM refined once less (its distance from the reference says how converged the reference is), `fem` the "
       "FEM behavior model as the "
       "hybrid steps it (implicit Euler at 1 ms), `springs` the default behavior model (symplectic Euler at 1 ms, "
       "its adaptive threshold), `modal` that FEM's lowest `modes` about rest (the default 32, and 128), each "
       "stepped exactly at 1 ms."},
      {"seen_vs_felt",
       "What is seen against what is felt, on the default scene's cube (3 cm) and organ (the liver, 4.5 cm, 16 nodes "
       "along it, its stiff lobe at +x): pressed from above at each of `points` points, 4 mm past the drawn surface "
       "and held 1.2 s, how much of the stylus tip's depth inside the object at rest the drawn surface has followed: "
       "one less the tip's distance inside the surface drawn over its distance inside the surface at rest (1: the "
       "surface follows the tip; less: the tip is drawn inside the object; more: the surface sinks past it); the "
       "smallest, the median and the largest; felt_rel_error, the largest relative difference of the force felt "
       "along the stylus's press (from the proxy to the HIP) from the behavior model's static force for that press of "
       "its drawn surface (behavior_surface_force along it, at every point); felt_rel_error_normal, "
       "the same for the normal force felt against a press along the normal as deep (on a slope, the stylus pressing "
       "straight down is not that press: the lattice is stiffer along some directions than others). Then let go over "
       "0.3 s: work_returned_max, the "
       "largest work the "
       "stylus got back over the work it did (at most 1: no energy created), and end_force_max, the largest force at "
       "a contact's last tick over its peak (small: the force tapers off rather than dropping as contact ends). The "
       "cube at its centre and three points a quarter of its size off; the organ every 2 mm along its length 2 mm off "
       "its middle line, and two points 4 mm to the other side."},
      {"stiffening",
       "Why some of those points sink less: at each, the behavior model's static force for a press of its drawn "
       "surface 4 mm deep over 40 times its force for 0.1 mm (behavior_surface_force; 1 for a linear model, less "
       "where cells give way, more where they stiffen); the smallest, the median and the largest, and the same at "
       "the force gain's points (gain_soft, gain_stiff). The force felt is the gain point's for the depth scaled by "
       "the compliance at rest: at a point that stiffens more than the gain point it is less than the behavior model's "
       "force for the depth (by about the ratio of the two), and the drawn surface sinks by less than the stylus. "
       "neighbours: along the organ's line, the largest ratio of two points' figures 2 mm apart (under a cell): near "
       "the spread over the whole organ, the differences are where a press lands on a cell, not regions a few gain "
       "points could be calibrated at."},
      {"force_vs_behavior",
       "The force felt (the S-Chain's times Hybrid::force_scale and Hybrid::follow, models/deformable/hybrid.h), "
       "held 0.9 s, against the behavior "
       "model's static force for a press of its drawn surface as deep (behavior_surface_force), 0.5 to 25 mm, at "
       "each side's gain point of the 10 cm cube with a stiff side (stiff_ratio 4): the largest relative difference "
       "(rel_error), and the largest ratio of the S-Chain alone to the behavior model."},
      {"press",
       "The behavior model's static force at the top centre of the 10 cm cube, every `step_mm` down to half its "
       "size: the springs with their volume floors (`floors` on, the default) and without, and the corotational "
       "FEM (`behavior` fem, 10 kPa, whose elements resist collapse themselves): `rises_to_mm` is how deep the force "
       "rises at every step before its first drop (a snap-through: the pressed mass punches through the layer "
       "below), `force_there_n` the force there, `drop_from_n` and `drop_to_n` the drop; ms_per_press the median "
       "time of one settled press (implicit Euler); omega_max (rad/s) the behavior model's spectrum bound and "
       "behavior_substeps its substeps per 1 ms step (symplectic Euler, the default)."}};
  s.plots = {{"visual_map",
              "ms",
              "rel_error",
              "ms per visual frame (median)",
              "relative error",
              {"method"},
              {"shape", "vertices"},
              {"method", "trilinear"}},
             {"schain_tick", "moved", "p50_us", "chains moved", "us per tick (p50)", {"elements"}, {}, {}}};
  s.goals = {
      {"haptic tick p99 within 100 us at 001's scale", "pipeline", "haptic_p99_us", 100, "scale", "seed"},
      {"haptic tick p99 within 200 us at 100 times that", "pipeline", "haptic_p99_us", 200, "scale", "100x"},
      {"visual frame within 2 ms (median) at 001's scale", "pipeline", "visual_frame_ms", 2, "scale", "seed"},
      {"haptic tick p99 within 100 us on the default scene's organ", "pipeline", "haptic_p99_us", 100, "scale",
       "organ"},
      {"visual frame within 2 ms (median) on the organ", "pipeline", "visual_frame_ms", 2, "scale", "organ"},
      {"the drawn cube sinks under the stylus by half its depth or more", "seen_vs_felt", "min_ratio", 0.5, "body",
       "cube", true},
      {"the drawn organ sinks under the stylus by half its depth or more", "seen_vs_felt", "min_ratio", 0.5, "body",
       "organ", true},
      {"force felt within 15 % of the behavior model's at every point of the cube", "seen_vs_felt", "felt_rel_error",
       0.15, "body", "cube"},
      {"force felt within 15 % of the behavior model's at every point of the organ", "seen_vs_felt", "felt_rel_error",
       0.15, "body", "organ"},
      {"no more work back than a press took (within 1e-9), cube", "seen_vs_felt", "work_returned_max", 1 + 1e-9, "body",
       "cube"},
      {"no more work back than a press took (within 1e-9), organ", "seen_vs_felt", "work_returned_max", 1 + 1e-9,
       "body", "organ"},
      {"no snap-through up to half the size, springs", "press", "rises_to_mm", 50, "floors", "on", true},
      {"no snap-through up to half the size, corotational FEM", "press", "rises_to_mm", 50, "behavior", "fem", true},
      {"force felt within 15 % of the behavior model to a quarter of the size", "force_vs_behavior", "rel_error",
       0.15}};
  return s;
}

}  // namespace hcosim::services::bench
