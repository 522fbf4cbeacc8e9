// The behavior model's static answers to a press, and the force gain that
// scales the S-Chain's force felt to them (001 §II: the haptic model's
// force is calibrated to the behavior model's, so that what the hand
// feels is what the eye sees sink).
#pragma once

#include <functional>
#include <vector>

#include <Eigen/Core>

#include "models/deformable/hybrid_spec.h"
#include "models/deformable/mvc.h"

namespace hcosim::models::deformable {

// N: the force on a holder keeping behavior mass `mass` of `spec` at its
// rest position plus `displacement` once the lattice has settled
// (implicit Euler to rest): the behavior model's static answer to a press
// of one of its masses.
Eigen::Vector3d behavior_static_force(const HybridSpec& spec, int mass, const Eigen::Vector3d& displacement);
// N, by depth: the behavior model's static answer to a press of the
// surface drawn: the force with which `spec`'s behavior model, loaded at
// the point of its visual rest surface nearest `point` as touch() loads a
// proxy there (along the surface's inward normal, or along `along` where
// it is not zero, spread over the face's vertices and by their rows of
// the visual map over the masses), sinks there by each
// of `depths` (m, > 0, increasing) along that direction once settled
// (implicit Euler to rest), pressed deeper step by step. The force felt
// is calibrated to it along the normal (force_gain). A stylus that comes
// in at an angle presses along its offset from the proxy, not the normal,
// and the lattice is stiffer along some directions than others: bench
// hybrid's seen_vs_felt row compares the force felt with both presses.
std::vector<double> behavior_surface_force(const HybridSpec& spec, const Eigen::Vector3d& point,
                                           const std::vector<double>& depths,
                                           const Eigen::Vector3d& along = Eigen::Vector3d::Zero());

// The force felt over the press's depth (the HIP's distance from the
// proxy): the behavior model's static force for a press of its drawn
// surface (behavior_surface_force) at 21 depths from 2 % to all of a
// quarter of the rest box's smallest side (0.5 to 25 mm for a 10 cm cube),
// at a gain point in the middle of the soft side's top and,
// with a stiff_ratio, of the stiff side's: the middle of a top cell's face
// beside the side's middle column (find_gain_point; bench hybrid's
// stiffening rows say how its stiffening under depth compares with other
// points'). An S-Chain moves more chains the deeper it is pressed, and its
// force grows far faster than the lattice's (bench hybrid's
// force_vs_behavior rows); touch() scales it to this (Hybrid::force_scale).
struct ForceGain {
  std::vector<double> depth;        // m, increasing
  std::vector<double> soft, stiff;  // N, the behavior model's force at each depth
  // m/N: the drawn surface's compliance at rest at each side's gain
  // point, and at every visual rest vertex (empty for a lattice of over
  // kMostMasses masses, whose stiffness is not factored).
  double soft_compliance = 0, stiff_compliance = 0;
  std::vector<double> compliance;
  static constexpr int kMostMasses = 20000;
  // N: the force at a depth on a side (the soft one's without a stiff
  // one), power_law between the samples.
  double at(double depth, bool stiff_side) const;
};
// Takes seconds: the behavior model settles at every depth, pressed in
// turn (implicit Euler to rest), on each side; and its rest stiffness is
// factored and forward-substituted for every visual vertex. `map`: the
// spec's visual map where the caller has it (what Hybrid::map() holds: a
// row per visual vertex, a column per cage mass); empty, it is computed.
ForceGain force_gain(const HybridSpec& spec, const Weights& map = {});
using GainSource = std::function<ForceGain(const HybridSpec&, const Weights& map)>;

// force_gain, computed once per process for each gain_key: tests and
// benches build many hybrids of one spec.
ForceGain shared_force_gain(const HybridSpec& spec, const Weights& map);

// y at x in a table of increasing xs and positive ys: the power law
// through the two samples beside it (a straight line on log scales, as the
// forces of a press grow), proportional to x below the first, and past
// the last the last two samples' power law; 0 where a sample is not positive.
double power_law(const std::vector<double>& xs, const double* ys, double x);

}  // namespace hcosim::models::deformable
