// The hybrid deformable model's specification (001 §II): its shape and
// size, the S-Chain's and the behavior model's materials, the visual mesh
// and its map; the checks of its fields; and the key that names the force
// gain a spec shapes (force_gain.h), for the caches that keep gains.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/deformable/limits.h"
#include "models/deformable/schain.h"
#include "models/fem/corotational.h"
#include "models/haptic/friction.h"
#include "models/massspring/lattice.h"
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

// Throws std::invalid_argument naming the first bad field and its range
// (limits.h; a shape's problems among them: not closed, no flat underside).
void check(const HybridSpec& spec);

// Throws std::invalid_argument("hybrid: " + what) unless `ok`: the hybrid
// model's argument checks, in every part of it.
void check_hybrid(bool ok, const std::string& what);

// Whether a rest point (world) is on the +x half past the body's centre
// that stiff_ratio stiffens (never without a stiff_ratio).
bool stiff_side(const HybridSpec& spec, const Eigen::Vector3d& rest);

// Raised whenever force_gain computes differently from the same spec, so
// that gains kept on disk by an older build are computed again.
constexpr int kForceGainVersion = 4;
// The force gain's key: kForceGainVersion, then every field of `spec` that
// force_gain reads (the shape's vertices and triangles last). Two specs
// with one key have one gain. Every field of HybridSpec and of the
// materials in it is named where the key is made, so that one added there
// does not compile until it is put in the key or said not to shape the gain.
std::vector<double> gain_key(const HybridSpec& spec);

}  // namespace hcosim::models::deformable
