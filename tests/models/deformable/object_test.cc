// Every kind of deformable object's reach (object.h): no contact begins
// outside it, and one begins just inside.
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "models/deformable/elastic_surface.h"
#include "models/deformable/hybrid.h"
#include "models/deformable/surface.h"

namespace hcosim::models::deformable {
namespace {

constexpr double kStep = 1e-3;  // s, the haptic step

// Each kind of deformable object, small enough for a unit test.
std::unique_ptr<Object> make(const std::string& kind) {
  SurfaceSpec surface;
  surface.resolution = 9;
  surface.options.dt = kStep;
  if (kind == "sheet") return std::make_unique<ElasticSurface>(surface);
  if (kind == "semisphere") {
    surface.shape = Shape::semisphere;
    surface.size = 0.03;
    surface.resolution = 6;
    return std::make_unique<ElasticSurface>(surface);
  }
  HybridSpec h;
  h.elements = 4;
  h.visual_subdivisions = 4;
  return std::make_unique<Hybrid>(h);
}

class DeformableReach : public ::testing::TestWithParam<std::string> {};

// No object begins a contact outside its reach (what a free-space answer
// rests on, docs/topics.md): a HIP brought to each point of a grid around
// the reach box, from far away, 0.5 mm outside it, touches nothing.
TEST_P(DeformableReach, NoContactBeginsOutsideIt) {
  const std::unique_ptr<Object> o = make(GetParam());
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
        EXPECT_FALSE(o->touch(kStep, p, false).in_contact) << "contact at " << p.transpose() << " outside the reach";
      }
}

// A HIP coming down over the middle from above the reach touches before
// it is half a millimetre under the object's drawn top, and inside the
// reach.
TEST_P(DeformableReach, AContactBeginsAtItsTopInsideTheReach) {
  const std::unique_ptr<Object> o = make(GetParam());
  const Eigen::AlignedBox3d r = o->reach();
  const double top = o->surface().row(2).maxCoeff();
  Eigen::Vector3d p(r.center().x() + 1e-4, r.center().y() + 1e-4, r.max().z() + 1e-3);
  Touch t;
  for (; p.z() > top - 5e-4 && !t.in_contact; p.z() -= 1e-5) t = o->touch(kStep, p, false);
  EXPECT_TRUE(t.in_contact) << "no contact down to " << p.transpose();
  EXPECT_TRUE(r.contains(p)) << "contact at " << p.transpose() << " outside the reach";
}

INSTANTIATE_TEST_SUITE_P(, DeformableReach, ::testing::Values("hybrid", "sheet", "semisphere"),
                         [](const ::testing::TestParamInfo<std::string>& i) { return i.param; });

}  // namespace
}  // namespace hcosim::models::deformable
