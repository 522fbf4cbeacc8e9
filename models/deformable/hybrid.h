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
#include <memory>
#include <vector>

#include "models/deformable/force_gain.h"
#include "models/deformable/hybrid_build.h"
#include "models/deformable/hybrid_spec.h"
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

class Hybrid final : public Object {
 public:
  // `map`, if given, stands in for mvc_map (for example a cache of it);
  // it must return points x cage weights. Ignored for the trilinear map.
  // `gain`, if given, stands in for force_gain (computed once per process
  // for each gain_key otherwise: shared_force_gain).
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
  // behavior model's for a press of the surface drawn here: at the gain
  // points its own, elsewhere as stiff as the surface is there at rest.
  double force_scale(int e, double depth, bool stiff) const;
  static constexpr double kPointSpread = 8;
  // How much harder than force_scale the force felt presses (away from
  // the gain points): 1 at each contact's start, then,
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
