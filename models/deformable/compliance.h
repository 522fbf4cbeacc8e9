// The hybrid model's drawn surface at rest as a spring: how far a point of
// it sinks under a unit force, spread over the behavior model's masses as
// touch() spreads the force felt. force_gain calibrates the force felt at
// its gain points and scales it elsewhere by this compliance.
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "models/deformable/hybrid_spec.h"
#include "models/deformable/mvc.h"
#include "models/fem/modal.h"
#include "models/massspring/lattice.h"

namespace hcosim::models::deformable {

// m/N, by row of `rows` (points x cage columns, each row summing to one):
// how far each point sinks along -normals.col(row) (unit) under 1 N
// pressing it there, spread over the masses `cage` names by its row, once
// `spec`'s behavior model on `lattice` has settled: the springs' axial
// stiffness at rest (no spring is stretched and no volume floor engaged
// there), the corotational FEM's, or with `modal` (the spec's modal model)
// the sum over its kept modes. One sparse factorisation of the stiffness,
// then for each point a forward substitution that visits only the columns
// its row reaches. Throws std::invalid_argument when the stiffness is
// singular (a mass held by nothing).
std::vector<double> surface_compliance(const HybridSpec& spec, const models::massspring::Lattice& lattice,
                                       const models::fem::Modal* modal, const Weights& rows,
                                       const std::vector<int>& cage, const Eigen::Matrix3Xd& normals);

// The modal model of a spec (BehaviorModel::modal: the corotational FEM's
// lowest spec.modes about rest); null for the other behavior models.
std::unique_ptr<models::fem::Modal> modal_of(const HybridSpec& spec);

}  // namespace hcosim::models::deformable
