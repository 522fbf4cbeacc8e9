// The hybrid deformable model (001 §II, Fig 3, 4, 6): an S-Chain haptic
// model computes the force at the servo rate; its moved chains are held
// in an adaptive mass-spring behavior model on the same lattice, which runs
// at its own rate; a dense visual mesh follows the behavior lattice through
// a precomputed map. One cube resting on its anchored bottom face, as in
// 001 Fig 7 and 8.
#pragma once

#include <functional>
#include <memory>
#include <vector>

#include "models/deformable/mvc.h"
#include "models/deformable/object.h"
#include "models/deformable/schain.h"
#include "models/massspring/mesh_lattice.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {

// How the visual mesh follows the behavior lattice: mean value coordinates
// on the lattice's boundary (dense, or truncated to `keep` of each row's
// weight), or trilinear embedding in the whole lattice.
enum class VisualMap { mvc, mvc_sparse, trilinear };
const char* name(VisualMap map);
VisualMap parse_visual_map(const std::string& name);  // throws std::invalid_argument listing the names

struct HybridSpec {
  int elements = 10;                                     // chains and masses per edge (10: 001 Fig 7's 1000)
  double size = 0.1;                                     // m, cube edge
  Eigen::Vector3d centre = Eigen::Vector3d(0, 0, 0.05);  // m, world; the bottom face is anchored
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
  int visual_subdivisions = 30;  // 6 s^2 + 2 vertices, 12 s^2 triangles (30: 5402 and 10800)
  double visual_exponent = 8;    // rounding of the visual box's edges (rounded_box)
  VisualMap map = VisualMap::mvc_sparse;
  double keep = 0.999;  // mvc_sparse: share of each row's weight kept
  // m: cage motions below this are not mapped (apply_moved); 10 um is a
  // hundredth of a pixel for a 600 px focal length at 0.5 m.
  double visual_tolerance = 1e-5;
};

// Throws std::invalid_argument naming the first bad field.
void check(const HybridSpec& spec);

// The chain lattice and the behavior lattice of `spec`, element e of one
// being mass e of the other.
ChainLattice hybrid_chains(const HybridSpec& spec);
models::massspring::Lattice hybrid_masses(const HybridSpec& spec);

// N: the force on a holder keeping behavior mass `mass` of `spec` at its
// rest position plus `displacement` once the lattice has settled
// (implicit Euler to rest): the behavior model's static answer to the
// press the S-Chain renders, which force_vs_behavior compares with it.
Eigen::Vector3d behavior_static_force(const HybridSpec& spec, int mass, const Eigen::Vector3d& displacement);

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
  explicit Hybrid(const HybridSpec& spec, const MapSource& map = {});

  // The HIP touches when it enters the cube's rest box; the surface element
  // nearest the entry point follows it until it leaves (or, with `grab`,
  // until grab ends).
  Touch touch(double dt, const Eigen::Vector3d& hip, bool grab) override;
  double behavior_dt() const override { return spec_.behavior.dt; }
  // couple(): holds each moved chain's mass at the chain's position and
  // releases the masses whose chains came back to rest; integrate(): steps
  // the behavior model.
  void couple() override;
  void integrate() override;
  // cage(): the displacements of the masses the map reads. surface_from:
  // the visual rest mesh plus their map, reading only the cage vertices
  // that moved (apply_moved); exactly the rest mesh at rest, whatever the
  // map's precision.
  Eigen::AlignedBox3d reach() const override { return {lo_, hi_}; }  // contact begins inside the rest box
  Eigen::Matrix3Xd cage() const override;
  Eigen::Matrix3Xd surface_from(const Eigen::Matrix3Xd& cage) const override;
  const std::vector<Eigen::Vector3i>& triangles() const override { return visual_.triangles; }

  const HybridSpec& spec() const { return spec_; }
  const SChain& haptic() const { return chains_; }
  const models::massspring::Simulator& behavior() const { return *masses_; }
  const models::massspring::State& state() const { return state_; }
  const models::massspring::TriangleMesh& visual_rest() const { return visual_; }
  const Weights& map() const { return weights_; }
  const std::vector<int>& cage_masses() const { return cage_; }  // masses the map reads, in its column order
  int simulated() const { return simulated_; }                   // masses the last behavior step integrated

 private:
  HybridSpec spec_;
  SChain chains_;
  std::unique_ptr<models::massspring::Simulator> masses_;
  models::massspring::State state_;
  models::massspring::TriangleMesh visual_;
  std::vector<int> cage_;  // masses whose positions the map reads, in its column order
  Weights weights_;
  ColumnWeights columns_;    // weights_ by columns, for apply_moved
  Eigen::Vector3d lo_, hi_;  // m, the rest box
  int contact_ = -1;
  Eigen::Vector3d normal_ = Eigen::Vector3d::UnitZ();  // outward normal of the face entered
  std::vector<int> held_;                              // masses held last step
  int simulated_ = 0;
};

}  // namespace hcosim::models::deformable
