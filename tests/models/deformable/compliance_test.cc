// The drawn surface's compliance at rest, against the behavior model
// itself settled under a small load (a dynamic relaxation, not the
// factorisation), and the modal model's with every mode against the FEM's.
#include <vector>

#include <gtest/gtest.h>

#include "models/deformable/compliance.h"
#include "models/deformable/hybrid_build.h"
#include "models/massspring/simulator.h"

namespace hcosim::models::deformable {
namespace {

// The seed's cube, small enough to settle in a moment, mapped trilinearly.
HybridSpec small_cube() {
  HybridSpec s;
  s.elements = 5;
  s.map = VisualMap::trilinear;
  return s;
}

// A point of the top near its centre and another near an edge, each
// pressed straight down.
struct Points {
  Eigen::Matrix3Xd at = Eigen::Matrix3Xd(3, 2);
  Eigen::Matrix3Xd normal = Eigen::Matrix3Xd(3, 2);
};
Points top_points(const HybridSpec& s) {
  Points p;
  const double top = rest_box(s).max().z();
  p.at.col(0) = s.centre + Eigen::Vector3d(0.003, -0.004, 0), p.at(2, 0) = top;
  p.at.col(1) = s.centre + Eigen::Vector3d(0.04, 0.03, 0), p.at(2, 1) = top;
  p.normal.colwise() = Eigen::Vector3d(0, 0, 1);  // the outward normal: the press is along -normal
  return p;
}

TEST(Compliance, IsHowFarTheSettledSpringsSinkUnderAUnitLoad) {
  const HybridSpec s = small_cube();
  const models::massspring::Voxels voxels = hybrid_voxels(s);
  const models::massspring::Lattice lattice = hybrid_masses(s);
  const Cage cage = map_cage(s, voxels, lattice, hybrid_visual(s));
  const Points p = top_points(s);
  const Weights rows = map_rows(s, voxels, cage, p.at);
  const std::vector<double> c = surface_compliance(s, lattice, nullptr, rows, cage.masses, p.normal);
  ASSERT_EQ(c.size(), 2u);
  models::massspring::Options o;
  o.integrator = models::massspring::Integrator::implicit_euler;
  o.dt = 1, o.tolerance = 1e-12;
  for (int k = 0; k < 2; ++k) {
    // 1 mN: small enough that the springs stay linear and no floor engages.
    const double f = 1e-3;
    std::vector<models::massspring::PointForce> loads;
    for (Weights::InnerIterator w(rows, k); w; ++w)
      loads.push_back({cage.masses[w.col()], -f * w.value() * Eigen::Vector3d(p.normal.col(k))});
    models::massspring::Simulator sim(lattice, o);
    models::massspring::State st = models::massspring::rest_state(lattice);
    for (int n = 0; n < 200; ++n) sim.step(st, loads);
    double sunk = 0;
    for (Weights::InnerIterator w(rows, k); w; ++w) {
      const int m = cage.masses[w.col()];
      sunk -= w.value() * p.normal.col(k).dot(st.x.col(m) - lattice.rest.col(m));
    }
    EXPECT_GT(c[k], 0);
    EXPECT_NEAR(sunk / f / c[k], 1, 1e-3) << "point " << k << ": settled " << sunk / f << " m/N, compliance " << c[k];
  }
  EXPECT_GT(c[1], c[0]) << "the edge of the top gives more than its middle";
}

TEST(Compliance, EveryModeOfTheModalModelIsTheFemsCompliance) {
  HybridSpec fem = small_cube();
  fem.behavior_model = BehaviorModel::fem;
  HybridSpec modal = fem, few = fem;
  modal.behavior_model = few.behavior_model = BehaviorModel::modal;
  modal.modes = 3 * 5 * 5 * 4;  // every free node's three
  few.modes = 6;
  const models::massspring::Voxels voxels = hybrid_voxels(fem);
  const models::massspring::Lattice lattice = hybrid_masses(fem);
  const Cage cage = map_cage(fem, voxels, lattice, hybrid_visual(fem));
  const Points p = top_points(fem);
  const Weights rows = map_rows(fem, voxels, cage, p.at);
  EXPECT_EQ(modal_of(fem), nullptr);
  const std::vector<double> full = surface_compliance(fem, lattice, nullptr, rows, cage.masses, p.normal);
  const std::vector<double> all =
      surface_compliance(modal, lattice, modal_of(modal).get(), rows, cage.masses, p.normal);
  const std::vector<double> some = surface_compliance(few, lattice, modal_of(few).get(), rows, cage.masses, p.normal);
  for (int k = 0; k < 2; ++k) {
    EXPECT_NEAR(all[k] / full[k], 1, 1e-6) << "point " << k;
    EXPECT_LT(some[k], all[k]) << "point " << k << ": fewer modes are stiffer";
  }
}

}  // namespace
}  // namespace hcosim::models::deformable
