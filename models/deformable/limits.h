// The ranges the deformable models' specs accept, in SI units. Each
// model's check() and the deployment's reader (adapters/deformable) hold a
// field to the same range, so that a value a deployment may give is one
// the model takes, and one it refuses is named where it is written.
#pragma once

#include <string>

namespace hcosim::models::deformable {

struct Range {
  double lo, hi;  // both included
  bool holds(double v) const { return v >= lo && v <= hi; }
  // "[lo, hi]", for messages.
  std::string text() const;
};

namespace limits {

inline constexpr Range kSize{0.01, 2};  // m: a cube's edge, a shape box's longest side, a sheet's edge, a dome's radius

// The hybrid model (hybrid_spec.h).
inline constexpr Range kElements{3, 100};            // chains and masses per edge
inline constexpr Range kStiffRatio{1, 100};          // the stiff side's over the soft side's
inline constexpr Range kVolume{0, 1000};             // the volume floors' bulk modulus, in springs' k over the spacing
inline constexpr Range kVisualSubdivisions{1, 300};  // the cube's visual mesh: squares per edge
inline constexpr Range kVisualExponent{2, 64};       // the rounding of the visual cube's edges
inline constexpr Range kKeep{0.5, 1};                // mvc_sparse: share of each map row's weight kept
inline constexpr Range kYoung{10, 1e8};              // Pa: the fem and modal behavior models' Young's modulus
inline constexpr Range kPoisson{0, 0.49};            // their Poisson's ratio, short of the locking of linear tetrahedra
inline constexpr Range kDensity{1, 20000};           // kg/m^3
inline constexpr Range kBehaviorRate{10, 10000};     // Hz: the behavior model's steps per second

// The elastic sheet and semi-sphere (elastic_surface.h).
inline constexpr Range kResolution{3, 200};           // a sheet's masses per edge, a dome's rings
inline constexpr Range kSpringStiffness{1e-3, 1e5};   // N/m per spring
inline constexpr Range kSpringDamping{0, 1e3};        // N s/m per spring
inline constexpr Range kPrestretch{0, 0.4};           // share of a sheet's springs' length
inline constexpr Range kBending{0, 1};                // J, flexural rigidity
inline constexpr Range kContactStiffness{1e-3, 1e6};  // N/m, the proxy's coupling to the stylus

}  // namespace limits
}  // namespace hcosim::models::deformable
