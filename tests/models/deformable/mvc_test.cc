// Mean value coordinates (Ju, Schaefer, Warren 2005), their truncated
// variant and trilinear embedding: linear precision inside, outside and on
// the cage, no NaN on its vertices, edges and faces, and affine cage motions
// carried exactly.
#include <gtest/gtest.h>

#include "models/deformable/mvc.h"

namespace hcosim::models::deformable {
namespace {

// The unit cube, 12 triangles counter-clockwise seen from outside.
struct Cage {
  Eigen::Matrix3Xd x;
  std::vector<Eigen::Vector3i> t;
};
Cage cube() {
  Cage c;
  c.x.resize(3, 8);
  for (int v = 0; v < 8; ++v) c.x.col(v) << (v & 1), (v >> 1) & 1, (v >> 2) & 1;
  c.t = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
         {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return c;
}

Eigen::Matrix3Xd probe_points() {
  Eigen::Matrix3Xd p(3, 10);
  p << 0.5, 0.2, 0.9, 0.5, 0.5, 0.0, 1.0, 0.3, 1.5, -0.4,   //
      0.5, 0.7, 0.1, 0.5, 0.0, 0.0, 0.5, 0.3, 0.5, 2.0,     //
      0.5, 0.4, 0.8, 1e-13, 0.0, 0.0, 1.0, 1.0, 0.5, -1.0;  //
  // centre, inside, inside, a hair above the bottom face, on a bottom edge,
  // on a vertex, on a top edge, on the top face, outside, far outside
  return p;
}

// Points from 1e-12 to 1e-3 off a face, on both sides, where the closed
// formula divides by the sine of a vanishing angle. Near enough, a point
// takes its projection's barycentric weights: the error is then at most
// its distance, and nowhere a loss of precision.
TEST(MeanValueCoordinates, NearFacePointsKeepLinearPrecision) {
  const Cage c = cube();
  std::vector<Eigen::Vector3d> pts;
  for (double d = 1e-12; d <= 1e-3; d *= 10)
    for (const double side : {-1.0, 1.0})
      for (const Eigen::Vector2d& xy :
           {Eigen::Vector2d(0.37, 0.61), Eigen::Vector2d(0.5, 0.5), Eigen::Vector2d(0.03, 0.2)})
        pts.emplace_back(xy.x(), xy.y(), side * d);
  Eigen::Matrix3Xd p(3, pts.size());
  for (std::size_t i = 0; i < pts.size(); ++i) p.col(i) = pts[i];
  const Weights w = mean_value_weights(c.x, c.t, p);
  const Eigen::Matrix3Xd got = apply(w, c.x);
  for (int i = 0; i < p.cols(); ++i) {
    const double d = std::abs(p(2, i));
    EXPECT_LE((got.col(i) - p.col(i)).norm(), d < 1e-4 ? d + 1e-12 : 1e-9) << "point " << p.col(i).transpose();
  }
}

TEST(MeanValueCoordinates, ReproduceLinearFunctionsEverywhere) {
  const Cage c = cube();
  const Eigen::Matrix3Xd p = probe_points();
  const Weights w = mean_value_weights(c.x, c.t, p);
  ASSERT_EQ(w.rows(), p.cols());
  for (int r = 0; r < w.rows(); ++r) {
    double sum = 0;
    for (Weights::InnerIterator it(w, r); it; ++it) {
      ASSERT_TRUE(std::isfinite(it.value())) << "point " << r;
      sum += it.value();
    }
    EXPECT_NEAR(sum, 1, 1e-12) << "point " << r;
  }
  EXPECT_LT((apply(w, c.x) - p).cwiseAbs().maxCoeff(), 1e-9);
  // On a vertex: that vertex alone.
  EXPECT_EQ(w.coeff(5, 0), 1);
  // Inside: all weights positive (MVC are positive in a convex cage).
  for (Weights::InnerIterator it(w, 1); it; ++it) EXPECT_GT(it.value(), 0);
}

TEST(MeanValueCoordinates, CarryAffineCageMotionsExactly) {
  const Cage c = cube();
  const Eigen::Matrix3Xd p = probe_points();
  const Weights w = mean_value_weights(c.x, c.t, p);
  Eigen::Matrix3d a;
  a << 1.2, 0.1, 0, -0.2, 0.9, 0.3, 0.05, 0, 1.1;
  const Eigen::Vector3d b(0.3, -0.1, 2);
  const Eigen::Matrix3Xd moved = (a * c.x).colwise() + b;
  const Eigen::Matrix3Xd expect = (a * p).colwise() + b;
  EXPECT_LT((apply(w, moved) - expect).cwiseAbs().maxCoeff(), 1e-9);
}

// The column-wise map of displacements agrees with the full map of moved
// positions: exactly up to float weights when every column is read, and
// within the tolerance when columns that moved less are skipped.
TEST(MeanValueCoordinates, MovedColumnsAgreeWithTheFullMap) {
  const Cage c = cube();
  const Eigen::Matrix3Xd p = probe_points();
  const Weights w = mean_value_weights(c.x, c.t, p);
  const ColumnWeights cols = w.cast<float>();
  const Eigen::Matrix3Xd rest = apply(w, c.x);
  Eigen::Matrix3Xd u = Eigen::Matrix3Xd::Zero(3, 8);
  u.col(7) << 0.01, -0.02, 0.03;  // one corner pulled 3 cm
  u.col(3) << 0, 0, 1e-6;         // one a micrometre
  const Eigen::Matrix3Xd full = apply(w, c.x + u);
  EXPECT_LT((apply_moved(cols, rest, u) - full).cwiseAbs().maxCoeff(), 1e-8);
  const Eigen::Matrix3Xd skipped = apply_moved(cols, rest, u, 1e-5);
  EXPECT_GT((skipped - full).cwiseAbs().maxCoeff(), 0);     // the micrometre column was skipped
  EXPECT_LT((skipped - full).cwiseAbs().maxCoeff(), 1e-6);  // at most the skipped micrometre
  EXPECT_THROW(apply_moved(cols, rest, u.leftCols(7)), std::invalid_argument);
}

// Truncation trades accuracy for fewer weights: keeping everything is the
// full map, and the error shrinks as more of each row is kept.
TEST(MeanValueCoordinates, TruncatedTradesAccuracyForSparsity) {
  const Cage c = cube();
  Eigen::Matrix3Xd p = 0.5 * (Eigen::Matrix3Xd::Random(3, 200).array() + 1).matrix();
  const Weights w = mean_value_weights(c.x, c.t, p);
  EXPECT_LT((apply(truncate(w, 1.0), c.x) - apply(w, c.x)).cwiseAbs().maxCoeff(), 1e-12);
  double last_error = 1e9;
  long last_nonzeros = 0;
  for (const double keep : {0.5, 0.8, 0.95, 0.999}) {
    const Weights t = truncate(w, keep);
    const double err = (apply(t, c.x) - p).norm() / p.norm();
    SCOPED_TRACE("keep " + std::to_string(keep));
    EXPECT_LT(err, last_error);
    EXPECT_GT(t.nonZeros(), last_nonzeros);
    EXPECT_LE(t.nonZeros(), w.nonZeros());
    for (int r = 0; r < t.rows(); ++r) EXPECT_NEAR(Eigen::RowVectorXd(t.row(r)).sum(), 1, 1e-12);
    last_error = err, last_nonzeros = t.nonZeros();
  }
  EXPECT_THROW(truncate(w, 0), std::invalid_argument);
}

TEST(MeanValueCoordinates, TrilinearReproducesLinearFunctionsInItsGrid) {
  Eigen::Matrix3Xd p = 0.02 * (Eigen::Matrix3Xd::Random(3, 50).array() + 1).matrix();  // in [0, 0.04]^3
  const Weights w = trilinear_weights(5, 5, 5, 0.01, Eigen::Vector3d::Zero(), p);
  Eigen::Matrix3Xd grid(3, 125);
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) grid.col(i + 5 * (j + 5 * k)) << 0.01 * i, 0.01 * j, 0.01 * k;
  EXPECT_LT((apply(w, grid) - p).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_THROW(trilinear_weights(1, 5, 5, 0.01, Eigen::Vector3d::Zero(), p), std::invalid_argument);
}

TEST(MeanValueCoordinates, BadInputIsRefused) {
  const Cage c = cube();
  Eigen::Matrix3Xd p(3, 1);
  p << NAN, 0, 0;
  EXPECT_THROW(mean_value_weights(c.x, c.t, p), std::invalid_argument);
  std::vector<Eigen::Vector3i> bad = c.t;
  bad[3] = {0, 1, 8};
  EXPECT_THROW(mean_value_weights(c.x, bad, probe_points()), std::invalid_argument);
  EXPECT_THROW(apply(mean_value_weights(c.x, c.t, probe_points()), Eigen::Matrix3Xd::Zero(3, 7)),
               std::invalid_argument);
}

}  // namespace
}  // namespace hcosim::models::deformable
