#include "models/deformable/hybrid_spec.h"

#include <cmath>
#include <stdexcept>

#include "models/fem/modal.h"

namespace hcosim::models::deformable {

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

void check_hybrid(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("hybrid: " + what);
}

void check(const HybridSpec& s) {
  const auto within = [](const char* field, double v, Range r) {
    check_hybrid(r.holds(v), std::string(field) + " must be in " + r.text());
  };
  within("elements", s.elements, limits::kElements);
  within("size", s.size, limits::kSize);
  check_hybrid(s.centre.allFinite(), "centre must be finite");
  within("stiff_ratio", s.stiff_ratio, limits::kStiffRatio);
  within("volume", s.volume, limits::kVolume);
  check_hybrid(s.volume_floor > 0 && s.volume_floor <= 1, "volume_floor must be in (0, 1]");
  within("modes", s.modes, Range{1, double(models::fem::Modal::kMaxDofs)});
  within("visual_subdivisions", s.visual_subdivisions, limits::kVisualSubdivisions);
  within("visual_exponent", s.visual_exponent, limits::kVisualExponent);
  within("keep", s.keep, limits::kKeep);
  within("young", s.fem.young, limits::kYoung);
  within("poisson", s.fem.poisson, limits::kPoisson);
  within("density", s.fem.density, limits::kDensity);
  within("behavior rate (1 / behavior.dt)", 1 / s.behavior.dt, limits::kBehaviorRate);
  check_hybrid(s.visual_tolerance >= 0 && s.visual_tolerance < s.size, "visual_tolerance must be in [0, size)");
  check_hybrid(s.tip_radius >= 0 && s.tip_radius < 0.5 * s.size, "tip_radius must be in [0, size / 2)");
  check_hybrid(s.shape.triangles.empty() || s.map != VisualMap::trilinear, "a shape is mapped by mvc or mvc_sparse");
}

bool stiff_side(const HybridSpec& s, const Eigen::Vector3d& rest) {
  return s.stiff_ratio != 1 && rest.x() > s.centre.x() + 1e-9 * s.size;
}

std::vector<double> gain_key(const HybridSpec& s) {
  // Structured bindings name every field: one added to a struct here
  // breaks the build until it is placed below.
  const auto& [elements, size, centre, shape, chain, relax_rate, limit_stiffness, material, behavior, stiff_ratio,
               volume, volume_floor, behavior_model, fem, modes, visual_subdivisions, visual_exponent, map, keep,
               visual_tolerance, friction, tip_radius] = s;
  const auto& [chain_stiffness, stretch, compress, shear] = chain;
  const auto& [mass, k, b, drag] = material;
  const auto& [young, poisson, density, alpha, beta] = fem;
  const auto& [vertices, triangles] = shape;
  // Not read by force_gain: the gain is the same wherever the body stands
  // (centre), it settles with its own steps (behavior), and it presses the
  // drawn rest surface itself, not the stylus's proxy on it (the visual
  // tolerance, friction and the tip's radius).
  (void)centre, (void)behavior, (void)visual_tolerance, (void)friction, (void)tip_radius;
  std::vector<double> key{double(kForceGainVersion), double(elements), size, chain_stiffness, stretch, compress, shear,
                          relax_rate, limit_stiffness, mass, k, b, drag, volume, volume_floor, stiff_ratio,
                          double(behavior_model), young, poisson, density, alpha, beta, double(modes),
                          // The surface pressed and its map's rows (a shape's own mesh is below).
                          double(visual_subdivisions), visual_exponent, double(map), keep};
  for (int v = 0; v < vertices.cols(); ++v)
    for (int c = 0; c < 3; ++c) key.push_back(vertices(c, v));
  for (const Eigen::Vector3i& t : triangles)
    for (int c = 0; c < 3; ++c) key.push_back(t[c]);
  return key;
}

}  // namespace hcosim::models::deformable
