// The hybrid deformable model (001) and seed 000's elastic surfaces: the
// seed's meshes, the visual map, release, monotone and non-homogeneous
// force, agreement of the S-Chain force with the behavior model's, and
// abuse by the haptic point.
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "models/deformable/elastic_surface.h"
#include "models/deformable/hybrid.h"
#include "models/deformable/surface.h"

namespace hcosim::models::deformable {
namespace {

double signed_volume(const Eigen::Matrix3Xd& x, const std::vector<Eigen::Vector3i>& t) {
  double v = 0;
  for (const auto& f : t) v += x.col(f[0]).dot(x.col(f[1]).cross(x.col(f[2]))) / 6;
  return v;
}

// The top-face element above the centre, offset by (dx, dy) elements.
int top(const HybridSpec& s, int dx = 0, int dy = 0) {
  const int n = s.elements;
  return (n / 2 + dx) + n * ((n / 2 + dy) + n * (n - 1));
}

// Presses element e's rest point `depth` down over 100 ticks, holds 200.
Touch press(Hybrid& h, int e, double depth) {
  const Eigen::Vector3d r = h.haptic().lattice().rest(e);
  Touch t;
  for (int k = 0; k < 300; ++k) {
    t = h.touch(1e-3, r - Eigen::Vector3d(0, 0, depth * std::min(1.0, (k + 1) / 100.0) - 1e-9), false);
    h.advance();
  }
  return t;
}

TEST(HybridSurfaces, SeedMeshesAreClosedAndFaceOutward) {
  const HybridSpec s;
  const models::massspring::TriangleMesh v = rounded_box(30, -Eigen::Vector3d::Ones(), Eigen::Vector3d::Ones(), 8);
  EXPECT_EQ(v.vertices.cols(), 5402);  // 001 Fig 7
  EXPECT_EQ(v.triangles.size(), 10800u);
  models::massspring::check_closed(v);
  EXPECT_GT(signed_volume(v.vertices, v.triangles), 0);
  const Eigen::Matrix3Xd n = vertex_normals(v.vertices, v.triangles);
  for (int i = 0; i < n.cols(); ++i) ASSERT_GT(n.col(i).dot(v.vertices.col(i)), 0) << "vertex " << i;

  const GridSurface g = grid_surface(10, 10, 10);
  EXPECT_EQ(g.nodes.size(), 488u);  // 1000 - 8^3
  EXPECT_EQ(g.triangles.size(), 972u);
  models::massspring::TriangleMesh cage{Eigen::Matrix3Xd(3, g.nodes.size()), g.triangles};
  for (std::size_t i = 0; i < g.nodes.size(); ++i)
    cage.vertices.col(i) << g.nodes[i] % 10, (g.nodes[i] / 10) % 10, g.nodes[i] / 100;
  models::massspring::check_closed(cage);
  EXPECT_NEAR(signed_volume(cage.vertices, cage.triangles), 729, 1e-9);
}

// The seed's visual mesh has face centres a rounding error off its cage's
// faces, where the closed mean value formula once lost 3 cm.
TEST(HybridVisualMap, SeedVisualMeshFollowsAffineCageMotionsForEveryMap) {
  for (VisualMap m : {VisualMap::mvc, VisualMap::mvc_sparse, VisualMap::trilinear}) {
    SCOPED_TRACE(name(m));
    HybridSpec s;
    s.map = m;
    const Hybrid h(s);
    const models::massspring::Lattice& lat = h.behavior().lattice();
    Eigen::Matrix3d a;
    a << 1.1, 0.2, 0, -0.1, 0.9, 0.05, 0.02, 0, 1.05;
    const Eigen::Vector3d b(0.01, -0.02, 0.03);
    const std::vector<int>& cage = h.cage_masses();
    Eigen::Matrix3Xd x(3, cage.size());
    for (std::size_t i = 0; i < cage.size(); ++i) x.col(i) = a * lat.rest.col(cage[i]) + b;
    const Eigen::Matrix3Xd expect = (a * h.visual_rest().vertices).colwise() + b;
    // Truncation keeps 0.999 of each row: linear precision to about that;
    // points within 1e-7 of the cage's size from a face take their projection's.
    EXPECT_LT((apply(h.map(), x) - expect).cwiseAbs().maxCoeff(), m == VisualMap::mvc_sparse ? 2e-4 : 1e-7);
  }
}

TEST(Hybrid, ReleaseReturnsToTheRestShape) {
  HybridSpec s;
  Hybrid h(s);
  const Touch t = press(h, top(s), 0.005);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(h.simulated(), 0);
  EXPECT_GT((h.surface() - h.visual_rest().vertices).cwiseAbs().maxCoeff(), 1e-3);
  for (int k = 0; k < 3000; ++k) h.touch(1e-3, s.centre + Eigen::Vector3d(0, 0, 0.2), false), h.advance();
  EXPECT_TRUE(h.haptic().moved().empty());
  EXPECT_LT((h.state().x - h.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-5);
  EXPECT_LT((h.surface() - h.visual_rest().vertices).cwiseAbs().maxCoeff(), 1e-5);
}

// Tests that do not concern the visual map use the one that costs nothing to build.
HybridSpec quick() {
  HybridSpec s;
  s.map = VisualMap::trilinear;
  return s;
}

TEST(Hybrid, ForceGrowsMonotonicallyWithDepth) {
  const HybridSpec s = quick();
  double last = 0;
  for (double depth = 0.001; depth <= 0.02; depth += 0.00125) {
    Hybrid h(s);
    const Touch t = press(h, top(s), depth);
    EXPECT_GT(t.force.z(), last) << "depth " << depth;
    EXPECT_NEAR(t.depth, depth, 1e-8);
    EXPECT_GT(t.stiffness, 0);
    last = t.force.z();
  }
}

TEST(Hybrid, StifferSidePushesBackHarderInBothModels) {  // 001 Fig 8
  HybridSpec s = quick();
  s.stiff_ratio = 4;
  Hybrid soft(s), hard(s);
  const double f_soft = press(soft, top(s, -3), 0.004).force.z();
  const double f_hard = press(hard, top(s, 3), 0.004).force.z();
  EXPECT_GT(f_hard, 2 * f_soft);
  const Eigen::Vector3d down(0, 0, -0.004);
  EXPECT_GT(behavior_static_force(s, top(s, 3), down).z(), 2 * behavior_static_force(s, top(s, -3), down).z());
}

// The S-Chain's K and ranges are fitted to the behavior model (hybrid.h):
// over 1 to 5 mm the two static forces agree within 15 %.
TEST(Hybrid, ChainForceAgreesWithTheBehaviorModel) {
  const HybridSpec s = quick();
  for (double depth = 0.001; depth <= 0.0051; depth += 0.001) {
    Hybrid h(s);
    const double chain = press(h, top(s), depth).force.z();
    const double behavior = behavior_static_force(s, top(s), Eigen::Vector3d(0, 0, -depth)).z();
    EXPECT_NEAR(chain / behavior, 1, 0.15) << "depth " << depth << ": chain " << chain << " N, behavior " << behavior;
  }
}

TEST(Hybrid, FarAndNanPointsAndAZeroStepAreHandled) {
  const HybridSpec s = quick();
  Hybrid h(s);
  EXPECT_FALSE(h.touch(1e-3, Eigen::Vector3d(1e3, -1e3, 1e3), false).in_contact);
  EXPECT_THROW(h.touch(1e-3, Eigen::Vector3d(NAN, 0, 0), false), std::invalid_argument);
  EXPECT_THROW(h.touch(0, s.centre, false), std::invalid_argument);
  EXPECT_TRUE(h.touch(1e-3, s.centre, false).in_contact);
}

// Teleported to the cube's centre, then held there for a simulated minute.
TEST(Hybrid, MinuteLongContactAtTheCentreStaysFinite) {
  const HybridSpec s = quick();
  Hybrid h(s);
  Touch t;
  for (int k = 0; k < 60000; ++k) {
    t = h.touch(1e-3, s.centre, false);
    if (k % 10 == 0) h.advance();
  }
  EXPECT_TRUE(t.in_contact);
  EXPECT_TRUE(t.force.allFinite());
  EXPECT_GT(t.force.norm(), 0);
  const Eigen::Matrix3Xd x = h.surface();
  EXPECT_TRUE(x.allFinite());
  EXPECT_EQ(x.cols(), 5402);
  EXPECT_TRUE(h.state().x.allFinite());
}

TEST(ElasticSurface, SheetPressedAtOneVertexPushesBackAndRecovers) {  // 000 §2.2
  SurfaceSpec s;
  s.options.dt = 1e-3;
  ElasticSurface sheet(s);
  EXPECT_FALSE(sheet.touch(1e-3, Eigen::Vector3d(0, 0, 0.01), false).in_contact);
  double last = 0;
  Touch t;
  for (int k = 1; k <= 500; ++k) {
    t = sheet.touch(1e-3, Eigen::Vector3d(0.001, 0, -0.01 * std::min(1.0, k / 200.0)), false);
    if (k % 50 == 0 && k <= 200) EXPECT_GT(t.force.z(), last), last = t.force.z();
  }
  EXPECT_TRUE(t.in_contact);
  EXPECT_NEAR(t.depth, 0.01, 1e-12);
  EXPECT_EQ(sheet.state().x(2, sheet.contact()), -0.01);
  for (int k = 0; k < 5000; ++k) sheet.touch(1e-3, Eigen::Vector3d(0, 0, 0.05), false);
  EXPECT_EQ(sheet.contact(), -1);
  EXPECT_LT((sheet.state().x - sheet.behavior().lattice().rest).cwiseAbs().maxCoeff(), 1e-6);
  EXPECT_THROW(sheet.touch(2e-3, Eigen::Vector3d::Zero(), false), std::invalid_argument);
}

TEST(ElasticSurface, SemiSphereDentsInwardAndItsMeshFacesOutward) {
  SurfaceSpec s;
  s.shape = Shape::semisphere;
  s.resolution = 8;
  s.size = 0.05;
  ElasticSurface dome(s);
  const Eigen::Matrix3Xd x = dome.surface();
  double flux = 0;
  const Eigen::Matrix3Xd n = vertex_normals(x, dome.triangles());
  for (int i = 0; i < n.cols(); ++i) flux += n.col(i).dot(x.col(i));
  EXPECT_GT(flux, 0);
  Touch t;
  for (int k = 1; k <= 400; ++k)
    t = dome.touch(1e-3, Eigen::Vector3d(0, 0, 0.05 - 0.005 * std::min(1.0, k / 200.0)), false);
  EXPECT_TRUE(t.in_contact);
  EXPECT_GT(t.force.z(), 0);
  EXPECT_TRUE(dome.state().x.allFinite());
}

// No object begins a contact outside its reach (what a free-space answer
// rests on, docs/topics.md): a HIP brought to each point of a grid around
// the reach box, from far away, 0.5 mm outside it, touches nothing; the
// same approach just inside the top face touches.
TEST(DeformableReach, NoContactBeginsOutsideTheReach) {
  std::vector<std::unique_ptr<Object>> objects;
  const double dt = 1e-3;
  HybridSpec h;
  h.elements = 4;
  h.visual_subdivisions = 4;
  objects.push_back(std::make_unique<Hybrid>(h));
  SurfaceSpec sheet;
  sheet.resolution = 9;
  sheet.options.dt = dt;
  objects.push_back(std::make_unique<ElasticSurface>(sheet));
  SurfaceSpec dome = sheet;
  dome.shape = Shape::semisphere;
  dome.size = 0.03;
  dome.resolution = 6;
  objects.push_back(std::make_unique<ElasticSurface>(dome));
  for (auto& o : objects) {
    const Eigen::AlignedBox3d r = o->reach();
    ASSERT_FALSE(r.isEmpty());
    for (int i = 0; i <= 4; ++i)
      for (int j = 0; j <= 4; ++j)
        for (int k = 0; k <= 4; ++k) {
          const Eigen::Vector3d f(i / 4.0, j / 4.0, k / 4.0);
          Eigen::Vector3d p = r.min() + f.cwiseProduct(r.sizes());
          // Onto the box's surface, then 0.5 mm out along the nearest face.
          int axis = 0, side = 0;
          double best = 1e9;
          for (int a = 0; a < 3; ++a)
            for (int sgn = 0; sgn < 2; ++sgn) {
              const double d = sgn ? r.max()[a] - p[a] : p[a] - r.min()[a];
              if (d < best) best = d, axis = a, side = sgn;
            }
          p[axis] = side ? r.max()[axis] + 5e-4 : r.min()[axis] - 5e-4;
          EXPECT_FALSE(o->touch(dt, p, false).in_contact) << "contact at " << p.transpose() << " outside the reach";
        }
  }
  // Just inside each reach, from above: a contact.
  for (auto& o : objects) {
    const Eigen::AlignedBox3d r = o->reach();
    const Eigen::Vector3d c = r.center();
    const Eigen::Vector3d top(c.x() + 1e-4, c.y() + 1e-4, r.max().z() - 5e-4);
    Touch t;
    for (int n = 0; n < 3; ++n) t = o->touch(dt, top, false);
    EXPECT_TRUE(t.in_contact) << "no contact just inside the reach at " << top.transpose();
  }
}

}  // namespace
}  // namespace hcosim::models::deformable
