// The hybrid deformable model (001 §II, Fig 3, 4, 6): an S-Chain haptic
// model computes the force at the servo rate; an adaptive mass-spring
// behavior model on the same lattice, which runs at its own rate, takes the
// opposite of that force; a dense visual mesh follows the behavior lattice
// through a precomputed map. The stylus touches the visual surface, the
// one drawn, through a proxy on it (models/deformable/proxy.h) with
// friction. A cube resting on its anchored bottom face, as in 001 Fig 7
// and 8, or an organ of any closed shape (001 Fig 9) resting on its
// underside.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "models/deformable/mvc.h"
#include "models/deformable/object.h"
#include "models/deformable/proxy.h"
#include "models/deformable/schain.h"
#include "models/fem/corotational.h"
#include "models/fem/modal.h"
#include "models/haptic/friction.h"
#include "models/massspring/mesh_lattice.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {

// How the visual mesh follows the behavior lattice: mean value coordinates
// on the lattice's boundary (dense, or truncated to `keep` of each row's
// weight), or trilinear embedding in the whole lattice.
enum class VisualMap { mvc, mvc_sparse, trilinear };
const char* name(VisualMap map);
VisualMap parse_visual_map(const std::string& name);  // throws std::invalid_argument listing the names

// The behavior model: 001 §II.A's mass-spring lattice, a corotational
// FEM of a material (models/fem) on the same nodes, or
// that FEM's lowest modes about rest (models/fem/modal.h).
enum class BehaviorModel { springs, fem, modal };
const char* name(BehaviorModel model);
BehaviorModel parse_behavior_model(const std::string& name);  // throws std::invalid_argument listing the names

struct HybridSpec {
  int elements = 10;                                     // chains and masses per edge (10: 001 Fig 7's 1000)
  double size = 0.1;                                     // m, the cube's edge, or the shape box's longest side
  Eigen::Vector3d centre = Eigen::Vector3d(0, 0, 0.05);  // m, world: the cube's or the shape box's centre
  // Empty: a cube. Otherwise a closed, outward-facing triangle mesh in any
  // unit and place, scaled so that its box's longest side is `size` and
  // moved so that its box's centre is `centre`: it is the visual mesh, and
  // the lattices fill the cells of size / (elements - 1) whose centres lie
  // inside it (massspring::voxelise). Either body rests on its lowest layer
  // of nodes, anchored: a shape needs a flat underside.
  models::massspring::TriangleMesh shape;
  // Haptic model: K and ranges fitted to the behavior model's static force
  // over 1 to 5 mm of depth (docs/deformable.md, force_vs_behavior).
  ChainMaterial chain{35, 0.3, 0.3, 0.6};
  double relax_rate = 50;                                       // 1/s, S-Chain relaxation
  double limit_stiffness = 1000;                                // N/m, past full compression
  models::massspring::Material material{1e-3, 50, 0.02, 0.01};  // behavior model, per mass and spring
  models::massspring::Options behavior = [] {
    models::massspring::Options o;
    o.integrator = models::massspring::Integrator::symplectic_euler;
    o.threshold = 1e-10;  // J: low enough that release returns to rest (hybrid_test)
    return o;
  }();
  // 001 Fig 8: the +x half is `stiff_ratio` times stiffer, in both models
  // (chain K times the ratio and its ranges divided by it; spring k times it).
  double stiff_ratio = 1;
  // Volume floors under the behavior lattice's tetrahedra (five to a cell,
  // models/massspring/quartet.h): below `volume_floor` of its rest volume
  // a tetrahedron resists with a bulk modulus of `volume` times the
  // springs' k over the lattice spacing (times stiff_ratio on the stiff
  // side), so that a collapsed or inverted cell comes back and a press does
  // not punch a mass through the layer below; above the floor the springs
  // act alone, as 001 §II.A has them. volume 0: no floors.
  double volume = 10;
  double volume_floor = 0.5;
  // With BehaviorModel::fem, the corotational FEM of `fem` on the lattice's
  // nodes, five tetrahedra to a cell (Young's modulus times stiff_ratio in
  // those whose four corners are on the stiff side), stepped by implicit
  // Euler at behavior.dt: `material`, the volume floors and the behavior
  // options' integrator and threshold then do not apply (corotated
  // elements resist collapse and inversion themselves). The default
  // material is soft tissue's order: 10 kPa, Poisson 0.3, 1000 kg/m^3,
  // mass damping 10/s.
  BehaviorModel behavior_model = BehaviorModel::springs;
  models::fem::Material fem{10e3, 0.3, 1000, 10, 0};
  // With BehaviorModel::modal, the lowest `modes` of that FEM linearised
  // at rest, each stepped exactly at behavior.dt (stable at any rate, the
  // cheapest per step; small strains only: no recovery from inversion).
  // Its eigensolve is dense, once, when the object is built: the
  // lattice's free nodes at most fem::Modal::kMaxDofs / 3 (the seed's
  // cube's 900 take about half a minute).
  int modes = 32;
  int visual_subdivisions = 30;           // the cube's: 6 s^2 + 2 vertices, 12 s^2 triangles (30: 5402 and 10800)
  double visual_exponent = 8;             // rounding of the visual cube's edges (rounded_box)
  VisualMap map = VisualMap::mvc_sparse;  // a shape's: mvc or mvc_sparse
  double keep = 0.999;                    // mvc_sparse: share of each row's weight kept
  // m: cage motions below this are not mapped (apply_moved); 10 um is a
  // hundredth of a pixel for a 600 px focal length at 0.5 m.
  double visual_tolerance = 1e-5;
  haptic::Friction friction;  // the stylus on the surface
  double tip_radius = 0;      // m, >= 0: the stylus tip's; its centre touches the surface grown by it
};

// Throws std::invalid_argument naming the first bad field (a shape's
// problems among them: not closed, no flat underside).
void check(const HybridSpec& spec);

// The body at rest: its box (m, world), its visual mesh (the rounded cube,
// or the placed shape), and the cells its lattices stand on.
Eigen::AlignedBox3d rest_box(const HybridSpec& spec);
models::massspring::TriangleMesh hybrid_visual(const HybridSpec& spec);
models::massspring::Voxels hybrid_voxels(const HybridSpec& spec);

// The chain lattice (an element at every node of the cells' grid, present
// where a mass is) and the behavior lattice of `spec` (masses numbered as
// Voxels::masses: for the cube, element e of one is mass e of the other).
ChainLattice hybrid_chains(const HybridSpec& spec);
models::massspring::Lattice hybrid_masses(const HybridSpec& spec);
// The FEM behavior model's mesh: the lattice's nodes and anchors, five
// tetrahedra to a cell, stiff_ratio in the stiff side's.
models::fem::Mesh hybrid_mesh(const HybridSpec& spec);

// N: the force on a holder keeping behavior mass `mass` of `spec` at its
// rest position plus `displacement` once the lattice has settled
// (implicit Euler to rest): the behavior model's static answer to a press
// of one of its masses.
Eigen::Vector3d behavior_static_force(const HybridSpec& spec, int mass, const Eigen::Vector3d& displacement);
// N, by depth: the behavior model's static answer to a press of the
// surface drawn: the force with which `spec`'s behavior
// model, loaded at the point of its visual rest surface nearest `point`
// as touch() loads a proxy there (along the surface's inward normal, or
// along `along` where it is not zero, spread over the face's vertices and
// by their rows of the visual map over the masses), sinks there by each
// of `depths` (m, > 0, increasing) along that direction once settled
// (implicit Euler to rest), pressed deeper step by step. The force felt
// is calibrated to it along the normal (force_gain), and force_vs_behavior
// compares the two. A stylus that comes in at an angle presses along its
// offset from the proxy, not the normal, and on the default organ's
// slopes the two presses take forces up to 40 % apart (bench hybrid's
// seen_vs_felt row compares the force felt with both: felt_rel_error
// 0.11, felt_rel_error_normal 0.40).
std::vector<double> behavior_surface_force(const HybridSpec& spec, const Eigen::Vector3d& point,
                                           const std::vector<double>& depths,
                                           const Eigen::Vector3d& along = Eigen::Vector3d::Zero());

// The force felt over the press's depth (the HIP's distance from the
// proxy): the behavior model's static force for a press
// of its drawn surface (behavior_surface_force) at 21 depths from 2 % to
// all of a quarter of the rest box's smallest side (0.5 to 25 mm for a 10
// cm cube), at a gain point in the middle of the soft side's top and,
// with a stiff_ratio, of the stiff side's: the middle of a top cell's face
// beside the side's middle column, where a press spreads over four masses
// (bench hybrid's stiffening rows say how its stiffening under depth
// compares with other points'). An S-Chain moves more chains the deeper it
// is pressed, and its force grows far faster than the lattice's (bench
// hybrid, force_vs_behavior rows: ten times it at 25 mm with the ranges
// fitted on 1 to 5 mm); touch() scales it to this (Hybrid::force_scale).
struct ForceGain {
  std::vector<double> depth;        // m, increasing
  std::vector<double> soft, stiff;  // N, the behavior model's force at each depth
  // m/N: the drawn surface's compliance at rest at each side's gain
  // point, and at every visual rest vertex (empty for a lattice of over
  // kMostMasses masses, whose stiffness is not factored).
  double soft_compliance = 0, stiff_compliance = 0;
  std::vector<double> compliance;
  static constexpr int kMostMasses = 20000;
  // N: the force at a depth, a power law between the samples (a straight
  // line on log scales), proportional to the depth below the first and
  // past the last.
  double at(double depth, bool stiff_side) const;
};
// Takes seconds: the behavior model settles at every depth, pressed in
// turn (implicit Euler to rest), on each side; and its rest stiffness is
// factored and forward-substituted for every visual vertex. `map`: the spec's visual
// map where the caller has it (what Hybrid::map() holds: a row per visual
// vertex, a column per cage mass); empty, it is computed.
ForceGain force_gain(const HybridSpec& spec, const Weights& map = {});
// The spec's fields force_gain reads, in a fixed order, after
// kForceGainVersion (the shape's vertices and triangles last): a cache's key.
std::vector<double> gain_inputs(const HybridSpec& spec);
// Raised whenever force_gain computes differently from the same spec, so
// that gains kept on disk by an older build are computed again.
constexpr int kForceGainVersion = 4;
using GainSource = std::function<ForceGain(const HybridSpec&, const Weights& map)>;

// The visual map of mean value weights (truncated for mvc_sparse) from the
// cage's rest positions (3 x n), its triangles and the visual rest points
// (3 x m): the slow part of building a Hybrid (about a second at seed
// scale). It depends on nothing else, so a service may keep it on disk.
Weights mvc_map(const HybridSpec& spec, const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                const Eigen::Matrix3Xd& points);
using MapSource = std::function<Weights(const Eigen::Matrix3Xd& cage, const std::vector<Eigen::Vector3i>& triangles,
                                        const Eigen::Matrix3Xd& points)>;

class Hybrid final : public Object {
 public:
  // `map`, if given, stands in for mvc_map (for example a cache of it);
  // it must return points x cage weights. Ignored for the trilinear map.
  // `gain`, if given, stands in for force_gain (computed once per process
  // for each spec otherwise).
  explicit Hybrid(const HybridSpec& spec, const MapSource& map = {}, const GainSource& gain = {});

  // The HIP touches where its path crosses the visual rest surface from
  // outside, or, for the first HIP seen, at the surface's nearest point if
  // it is inside: a proxy there (a material point of the visual mesh) stays on
  // that surface, sliding over it as friction lets it, until the HIP is
  // back outside its tangent plane (or, with `grab`, until grab ends: then
  // it sticks and may pull). The S-Chain element nearest the proxy is moved
  // by the HIP's offset from the proxy; the chains' force times the force
  // scale at that offset's length there (force_scale) and follow() is the
  // force on the stylus, kept inside the friction cone, and within what
  // the stylus has put in: at most kReturn times the work it has done on
  // the object since the contact began over the offset's length, so that
  // no press gives back more work than it took and the force tapers off
  // as the stylus comes out.
  Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) override;
  double behavior_dt() const override { return spec_.behavior.dt; }
  // couple(): the behavior model's loads for its next step, the opposite of
  // the forces felt since the last one (their mean), spread from the
  // proxy's visual vertices over the masses the map reads by the map's own
  // weights, and follow() moved toward the behavior model's sink (without
  // the modal model, which is linear, so force_scale is already its own,
  // and rings); integrate(): steps the behavior model under them.
  void couple() override;
  void integrate() override;
  // cage(): the displacements of the masses the map reads. surface_from:
  // the visual rest mesh plus their map, reading only the cage vertices
  // that moved (apply_moved); exactly the rest mesh at rest, whatever the
  // map's precision.
  // Contact begins inside the rest box grown by the tip's radius.
  Eigen::AlignedBox3d reach() const override {
    return {lo_ - Eigen::Vector3d::Constant(spec_.tip_radius), hi_ + Eigen::Vector3d::Constant(spec_.tip_radius)};
  }
  Eigen::Matrix3Xd cage() const override;
  Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const override;
  const std::vector<Eigen::Vector3i>& triangles() const override { return visual_.triangles; }

  const HybridSpec& spec() const { return spec_; }
  const SChain& haptic() const { return chains_; }
  const models::massspring::Simulator& behavior() const { return *masses_; }
  const models::massspring::State& state() const { return state_; }
  const models::massspring::TriangleMesh& visual_rest() const { return visual_; }
  const Weights& map() const { return weights_; }
  const ForceGain& gain() const { return gain_; }
  // A side's gain point (rest, world; ForceGain); the soft side's for both
  // without a stiff_ratio.
  const Eigen::Vector3d& gain_point(bool stiff) const { return gain_points_[stiff]; }
  // What touch() multiplies the S-Chain's force by where the proxy is,
  // pressed `depth` (m) into chain element e on the soft or stiff side:
  // the force gain's force at that depth on that side, times how much
  // stiffer the drawn surface is here than at the side's gain point (its
  // compliance at rest, interpolated over the proxy's face from its
  // vertices' (ForceGain::compliance), kept within [1 / kPointSpread,
  // kPointSpread]; 1 where the gain has none for this object's vertices),
  // over the S-Chain's steady force for that press of e (along the normal
  // of the visual vertex nearest it; the side's gain element's for an
  // anchored one). Once the chains have relaxed, the force felt is the
  // behavior model's for a press of the surface drawn here (issue 26
  // item 4): at the gain points its own, elsewhere as stiff as the
  // surface is there at rest.
  double force_scale(int e, double depth, bool stiff) const;
  static constexpr double kPointSpread = 8;
  // How much harder than force_scale the force felt presses (issue 26
  // item 4 away from the gain points): 1 at each contact's start, then,
  // at each couple() while the HIP presses within 60 degrees of the
  // normal and deeper than kFollowFrom, times the press's depth over how
  // far the drawn surface has sunk (sunk()) to the power behavior dt over
  // kFollowTime, each ratio within [1/2, 2] and never above 1 while the
  // work stored holds the force back; within [1 / kFollowSpread,
  // kFollowSpread]. Once the behavior model has settled, the drawn surface
  // under the proxy has sunk by the stylus's depth and the force felt is
  // the behavior model's for that press, where the work stored allows.
  double follow() const { return follow_; }
  // m: how far the drawn surface has sunk under the stylus along the line
  // from the proxy's point of the drawn rest surface toward the HIP: the
  // larger of where the surface drawn now crosses that line (a press moves
  // the surface sideways too) and how far the proxy's own material point
  // went along it (past a cell that gives way, the crossing is elsewhere
  // on the surface: following it would push the point through). 0 without
  // contact.
  double sunk() const;
  static constexpr double kFollowFrom = 1e-4;  // m
  static constexpr double kFollowTime = 0.1;   // s
  static constexpr double kFollowSpread = 8;
  static constexpr double kReturn = 3;  // a force growing as the offset squared or slower is never held back
  const std::vector<int>& cage_masses() const { return cage_; }  // masses the map reads, in its column order
  int simulated() const { return simulated_; }                   // masses the last behavior step integrated
  int substeps() const { return substeps_; }                     // substeps the last behavior step took
  // The proxy's material point on the visual mesh (face -1: no contact),
  // and where it is on the rest surface grown by the tip's radius (the
  // tip's centre).
  const SurfacePoint& contact() const { return contact_; }
  Eigen::Vector3d proxy() const;
  // N, by mass: the load the last touch() put on the behavior model; its
  // sum is minus the force felt (the map's rows sum to one).
  const Eigen::Matrix3Xd& tick_load() const { return tick_load_; }

 private:
  HybridSpec spec_;
  SChain chains_;
  ForceGain gain_;
  std::vector<double> chain_force_;                        // N, by chain element and gain depth: force_scale's
  int gain_elements_[2] = {-1, -1};                        // the soft and stiff sides' gain elements
  Eigen::Vector3d gain_points_[2];                         // and their gain points
  std::unique_ptr<models::massspring::Simulator> masses_;  // its lattice gives either model's nodes
  std::unique_ptr<models::fem::Corotational> fem_;         // BehaviorModel::fem
  std::unique_ptr<models::fem::Modal> modal_;              // BehaviorModel::modal
  models::massspring::State state_;
  models::massspring::TriangleMesh visual_;
  std::vector<int> cage_;  // masses whose positions the map reads, in its column order
  Weights weights_;
  ColumnWeights columns_;    // weights_ by columns, for apply_moved
  Eigen::Vector3d lo_, hi_;  // m, the rest box
  std::unique_ptr<MeshProxy> mesh_;
  Eigen::Matrix3Xd surface_;         // the visual rest mesh grown by the tip's radius: where the proxy lives
  std::unique_ptr<FaceGrid> faces_;  // of surface_, for entry
  std::vector<int> near_;            // the faces near the HIP's path, kept between ticks
  haptic::FrictionCone cone_;
  SurfacePoint contact_;
  Eigen::Vector3d last_hip_ = Eigen::Vector3d::Zero();
  bool has_last_ = false;
  Eigen::Matrix3Xd tick_load_;                 // N, by mass: the last touch's
  Eigen::Matrix3Xd load_sum_;                  // N, by mass: summed over the touches since couple()
  int load_ticks_ = 0;                         // touches summed
  std::vector<int> tick_masses_, sum_masses_;  // the columns of tick_load_ and load_sum_ that may be nonzero
  static constexpr std::uint8_t kInTick = 1, kInSum = 2;
  std::vector<std::uint8_t> listed_;                   // by mass: kInTick, kInSum, where it is listed
  std::vector<models::massspring::PointForce> loads_;  // the next behavior step's
  int simulated_ = 0;
  int substeps_ = 0;
  double follow_ = 1;    // follow()
  double stored_ = 0;    // J: the work the stylus has done on the object since the contact began
  bool capped_ = false;  // whether the last touch's force was held back to the work stored
  Eigen::Vector3d moved(const SurfacePoint& q) const;  // m: the visual surface's displacement at q
  static constexpr int kSunkWalks = 3;                 // sunk()'s steps toward the line
};

}  // namespace hcosim::models::deformable
