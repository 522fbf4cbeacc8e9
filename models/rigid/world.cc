#include "models/rigid/world.h"

#include "models/rigid/collide.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

namespace hcosim::models::rigid {

namespace {

// Passes over the contacts in a step where bodies touch each other.
constexpr int kContactPasses = 30;
// The share of a resting contact's overlap undone per step: all of it at
// once lifts a rocking cube by its deepest corner every step, which pumps
// the rocking.
constexpr double kRestingUndo = 0.2;

Eigen::Matrix3d cross_matrix(const Eigen::Vector3d& r) {
  Eigen::Matrix3d m;
  m << 0, -r.z(), r.y(), r.z(), 0, -r.x(), -r.y(), r.x(), 0;
  return m;
}

void check(const Material& m, const char* what) {
  if (!(m.restitution >= 0 && m.restitution <= 1))
    throw std::invalid_argument(std::string("rigid: ") + what + " restitution must be in [0, 1]");
  if (!(m.friction >= 0 && std::isfinite(m.friction)))
    throw std::invalid_argument(std::string("rigid: ") + what + " friction must be >= 0");
}

// Rotation by w over dt, as a quaternion.
Eigen::Quaterniond rotation(const Eigen::Vector3d& w, double dt) {
  const double angle = w.norm() * dt;
  if (angle == 0) return Eigen::Quaterniond::Identity();
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, w.normalized()));
}

// Points of the body that can touch the plane z = 0: a sphere's lowest
// point, a cube's corners (no allocation: this runs every step).
struct Support {
  std::array<Eigen::Vector3d, 8> p;
  int n = 0;
};
Support support_points(const Body& b) {
  Support s;
  if (b.shape == Shape::sphere) {
    s.p[0] = b.x - b.size * Eigen::Vector3d::UnitZ(), s.n = 1;
    return s;
  }
  const Eigen::Matrix3d R = b.q.toRotationMatrix();
  for (int c = 0; c < 8; ++c)
    s.p[std::size_t(c)] = b.x + R * (b.size * Eigen::Vector3d(c & 1 ? 1 : -1, c & 2 ? 1 : -1, c & 4 ? 1 : -1));
  s.n = 8;
  return s;
}

// The impulse on the second of two touching things whose relative
// velocity at the contact is v (second minus first) and changes by K per
// unit impulse on the second (the first taking the opposite); n is the
// unit normal out of the first.
Eigen::Vector3d impulse(const Eigen::Matrix3d& K, Eigen::Vector3d v, const Eigen::Vector3d& n, const Material& m) {
  const double vn0 = v.dot(n);
  // A grazing touch's normal is perpendicular to the motion only to
  // within rounding (amplified near tangency): approaches slower than a
  // millionth of the relative speed exchange nothing.
  if (vn0 >= -1e-6 * v.norm()) return Eigen::Vector3d::Zero();
  const double e = m.restitution, mu = m.friction, knn = n.dot(K * n);
  if (mu == 0) return -(1 + e) * vn0 / knn * n;  // Newton's law, exact
  const Eigen::Vector3d t1 = n.unitOrthogonal(), t2 = n.cross(t1);
  Eigen::Matrix2d Ktt;
  Ktt << t1.dot(K * t1), t1.dot(K * t2), t2.dot(K * t1), t2.dot(K * t2);
  const Eigen::Vector2d Ktn(t1.dot(K * n), t2.dot(K * n));
  // Contact point on the line through the centre (every sphere hit, a
  // cube's face centre): normal and tangential motion decouple, the slip
  // keeps its direction and slows linearly with the normal impulse, and
  // the impulse has a closed form: sliding throughout, or stopping.
  const double scale = Ktt.trace();
  if (Ktn.norm() <= 1e-12 * scale && std::abs(Ktt(0, 1)) <= 1e-12 * scale &&
      std::abs(Ktt(0, 0) - Ktt(1, 1)) <= 1e-12 * scale) {
    const double pn = -(1 + e) * vn0 / knn;
    const Eigen::Vector3d vt = v - vn0 * n;
    const double slip = vt.norm(), kt = Ktt(0, 0);
    if (slip == 0) return pn * n;
    return pn * n - std::min(mu * pn, slip / kt) * (vt / slip);
  }
  // Otherwise the slip can stop or turn during the impact, so the
  // impulse is integrated over the normal impulse (Routh; Stronge's
  // energetic restitution for a compression then a restitution phase):
  // each increment's friction opposes the current slip, or holds it at
  // zero when the cone allows.
  constexpr int kSteps = 400;
  const double dp = -vn0 / knn / kSteps;
  // The increment that keeps a stopped slip at zero: its tangential part
  // solves (K dP)_t = 0, limited to the friction cone.
  const Eigen::Vector2d x = -Ktt.ldlt().solve(dp * Ktn);
  const Eigen::Vector3d hold = x[0] * t1 + x[1] * t2;
  const Eigen::Vector3d stick = dp * n + (x.norm() <= mu * dp ? hold : Eigen::Vector3d(hold * (mu * dp / x.norm())));
  Eigen::Vector3d P = Eigen::Vector3d::Zero();
  double compression = -1;  // the normal impulse when the approach ended
  for (int k = 0; k < 100 * kSteps; ++k) {
    if (compression < 0 && v.dot(n) >= 0) compression = P.dot(n);
    if (compression >= 0 && P.dot(n) >= (1 + e) * compression) break;
    const Eigen::Vector3d vt = v - v.dot(n) * n;
    Eigen::Vector3d dP = stick;
    if (vt.norm() > 0) {
      // Sliding, unless this increment would reverse the slip: it stops.
      const Eigen::Vector3d slide = dp * (n - mu * vt.normalized());
      const Eigen::Vector3d after = v + K * slide;
      if ((after - after.dot(n) * n).dot(vt) > 0) dP = slide;
    }
    v += K * dP;
    P += dP;
  }
  return P;
}

}  // namespace

Eigen::Vector3d contact_impulse(const Body& b, double tip_mass, const Eigen::Vector3d& tip_v, const Eigen::Vector3d& p,
                                const Eigen::Vector3d& n, const Material& m) {
  // K = (1/m_t + 1/m_b) I - [r]x^2 / I_b.
  const Eigen::Matrix3d rx = cross_matrix(p - b.x);
  const Eigen::Matrix3d K = (1 / tip_mass + 1 / b.mass) * Eigen::Matrix3d::Identity() - rx * rx / inertia(b);
  return impulse(K, tip_v - point_velocity(b, p), n, m);
}

Eigen::Vector3d pair_impulse(const Body& a, const Body& b, const Eigen::Vector3d& p, const Eigen::Vector3d& n,
                             const Material& m) {
  // K = (1/m_a + 1/m_b) I - [r_a]x^2 / I_a - [r_b]x^2 / I_b.
  const Eigen::Matrix3d ra = cross_matrix(p - a.x), rb = cross_matrix(p - b.x);
  const Eigen::Matrix3d K =
      (1 / a.mass + 1 / b.mass) * Eigen::Matrix3d::Identity() - ra * ra / inertia(a) - rb * rb / inertia(b);
  return impulse(K, point_velocity(b, p) - point_velocity(a, p), n, m);
}

double time_of_impact(const Body& b, const Tip& tip, double tip_radius, double dt) {
  const Eigen::Vector3d q0 = tip.x - b.x, u = tip.v - b.v;
  if (b.shape == Shape::sphere) {
    // |q0 + u t| = R: the smaller root of a quadratic.
    const double R = b.size + tip_radius, c = q0.squaredNorm() - R * R;
    if (c <= 0) return 0;
    const double a = u.squaredNorm(), half_b = q0.dot(u);
    if (a == 0 || half_b >= 0) return -1;
    const double disc = half_b * half_b - a * c;
    if (disc < 0) return -1;
    const double t = c / (-half_b + std::sqrt(disc));  // = (-half_b - sqrt(disc)) / a, without cancellation
    return t <= dt ? t : -1;
  }
  // Conservative advancement: the signed distance changes no faster than
  // the relative speed, so stepping by distance / speed never skips a touch.
  const double speed = u.norm();
  Body moved = b;
  double t = 0;
  for (int k = 0; k < 200 && t <= dt; ++k) {
    moved.x = b.x + b.v * t;
    const double d = nearest(moved, tip.x + tip.v * t).distance - tip_radius;  // to the rounded box
    if (d <= 1e-9 * b.size) return t;
    if (speed == 0) return -1;
    t += d / speed;
  }
  return -1;
}

void check(const WorldSpec& spec) {
  if (!spec.gravity.allFinite()) throw std::invalid_argument("rigid: gravity is not finite");
  check(spec.tip, "tip");
  check(spec.floor, "floor");
  check(spec.pair, "pair");
  const Drag& d = spec.drag;
  if (!(d.linear >= 0 && d.quadratic >= 0 && d.angular_linear >= 0 && d.angular_quadratic >= 0))
    throw std::invalid_argument("rigid: drag coefficients must be >= 0");
  if (!(spec.tip_radius >= 0)) throw std::invalid_argument("rigid: tip_radius must be >= 0");
  if (!(spec.tip_mass > 0)) throw std::invalid_argument("rigid: tip_mass must be > 0");
  if (!(spec.sleep_speed >= 0 && spec.sleep_time > 0)) throw std::invalid_argument("rigid: bad sleep thresholds");
}

void check(const std::vector<Body>& bodies) {
  for (std::size_t i = 0; i < bodies.size(); ++i) {
    try {
      check(bodies[i]);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("body " + std::to_string(i) + ": " + e.what());
    }
  }
}

World::World(const WorldSpec& spec, std::vector<Body> bodies)
    : spec_(spec), bodies_(std::move(bodies)), loads_(bodies_.size()) {
  check(spec_);
  check(bodies_);
}

void World::set_load(std::size_t i, const Eigen::Vector3d& force, const Eigen::Vector3d& torque) {
  if (i >= bodies_.size()) throw std::invalid_argument("rigid: no body " + std::to_string(i) + " to load");
  if (!force.allFinite() || !torque.allFinite()) throw std::invalid_argument("rigid: load is not finite");
  loads_[i] = {force, torque};
}

void World::set_tip(const Tip& t) {
  if (!t.x.allFinite() || !t.v.allFinite()) throw std::invalid_argument("rigid: tip state is not finite");
  tip_ = t;
}

void World::hit(Body& b, double dt, StepReport& r) {
  const double t = time_of_impact(b, tip_, spec_.tip_radius, dt);
  if (t < 0) return;
  Body at = b;
  at.x = b.x + b.v * t;
  const Eigen::Vector3d tip_x = tip_.x + tip_.v * t;
  const Nearest c = nearest(at, tip_x);
  // The contact point on the tip's side of the touch (the body's surface
  // point lies within the touch tolerance of it): tip and body then take
  // their impulses on one line, and angular momentum is kept to rounding.
  const Eigen::Vector3d p = tip_x - spec_.tip_radius * c.normal;
  const Eigen::Vector3d P = contact_impulse(at, spec_.tip_mass, tip_.v, p, c.normal, spec_.tip);
  if (P.isZero()) return;
  const Eigen::Vector3d tip_v = tip_.v, body_v = b.v;
  tip_.v += P / spec_.tip_mass;
  b.v -= P / b.mass;
  b.w -= (p - at.x).cross(P) / inertia(b);
  // Positions such that moving the whole step at the new velocities passes
  // through the contact at t: the motion is exact piecewise, and momentum
  // about any point is conserved at every instant.
  tip_.x += (tip_v - tip_.v) * t;
  b.x += (body_v - b.v) * t;
  b.sleeping = false, b.still_s = 0;
  ++r.hits;
}

// Impulses at the body's points touching the plane: the normal impulse
// never pulls, friction stays in its cone, and impacts
// faster than bounce_speed bounce with the floor's restitution.
void World::floor(Body& b, double dt) const {
  struct Touch {
    Eigen::Vector3d r;
    double target = 0, normal = 0;
    Eigen::Vector2d tangent = Eigen::Vector2d::Zero();
  };
  std::array<Touch, 8> touches;
  std::size_t count = 0;
  const double slop = 1e-3 * b.size;
  const Support s = support_points(b);
  for (int i = 0; i < s.n; ++i) {
    const Eigen::Vector3d& p = s.p[std::size_t(i)];
    if (p.z() > slop) continue;
    Touch& t = touches[count++];
    t.r = p - b.x;
    const double vn = point_velocity(b, p).z();
    // A slow corner still above the plane may close its gap this step: a
    // cube resting a little tilted on its corners settles flat instead of
    // being held tilted.
    t.target = vn < -spec_.bounce_speed ? -spec_.floor.restitution * vn : -std::max(0.0, p.z()) / dt;
  }
  const double I = inertia(b), mu = spec_.floor.friction;
  auto apply = [&](const Eigen::Vector3d& r, const Eigen::Vector3d& P) {
    b.v += P / b.mass;
    b.w += r.cross(P) / I;
  };
  auto k = [&](const Eigen::Vector3d& r, const Eigen::Vector3d& d) {
    return 1 / b.mass + r.cross(d).squaredNorm() / I;
  };
  // Jacobi sweeps: every touch's impulse from the same velocities, each
  // applied at 1/n, so that symmetric touches (a cube flat on the plane)
  // get equal impulses. Gauss-Seidel sweeps in any order tilt a resting
  // cube a little each step toward the corner visited first.
  const Eigen::Vector3d ez = Eigen::Vector3d::UnitZ();
  if (count == 0) return;
  const double relax = 1.0 / double(count);
  std::array<Eigen::Vector3d, 8> impulses;
  for (int iter = 0; iter < 30; ++iter) {
    const Eigen::Vector3d v0 = b.v, w0 = b.w;
    for (std::size_t i = 0; i < count; ++i) {
      Touch& t = touches[i];
      const Eigen::Vector3d v = v0 + w0.cross(t.r);
      const double total = std::max(0.0, t.normal + relax * (t.target - v.z()) / k(t.r, ez));
      Eigen::Vector2d tangent = t.tangent;
      tangent.x() -= relax * v.x() / k(t.r, Eigen::Vector3d::UnitX());
      tangent.y() -= relax * v.y() / k(t.r, Eigen::Vector3d::UnitY());
      if (tangent.norm() > mu * total) tangent *= mu * total / tangent.norm();
      impulses[i] = Eigen::Vector3d(tangent.x() - t.tangent.x(), tangent.y() - t.tangent.y(), total - t.normal);
      t.normal = total, t.tangent = tangent;
    }
    for (std::size_t i = 0; i < count; ++i) apply(touches[i].r, impulses[i]);
  }
}

// The impulses at the pair's contact. An impact (approaching faster than
// bounce_speed) takes one impulse at the contact point, with restitution;
// a resting contact takes one at each support corner of a cube on a cube
// (Jacobi: all from the same velocities, each applied at 1/n, as on the
// plane), so that a face rests flat. On the first pass of a step (`first`)
// part of the overlap is undone along the normal in inverse proportion to
// the masses, which keeps their centre of mass. A sleeping body holds like
// a fixed one under a contact that carries no more than the other's
// weight (a body resting on it), and wakes under anything more (a push,
// a hit). Returns whether they touch.
bool World::touch(Body& a, Body& b, bool first, double dt, StepReport& r) const {
  if (a.sleeping && b.sleeping) return false;
  Contact c;
  if (!collide(a, b, 1e-4 * std::min(a.size, b.size), c)) return false;
  Material m = spec_.pair;
  const bool impact = (point_velocity(b, c.point) - point_velocity(a, c.point)).dot(c.normal) < -spec_.bounce_speed;
  if (!impact) m.restitution = 0;
  const bool spread = !impact && c.supports > 1;
  const int n = spread ? c.supports : 1;
  const auto at = [&](int k) -> const Eigen::Vector3d& { return spread ? c.support[std::size_t(k)] : c.point; };
  // The sleeper, if any, as a body too heavy to move.
  Body* sleeper = a.sleeping ? &a : b.sleeping ? &b : nullptr;
  Body* awake = sleeper == &a ? &b : &a;
  Body fixed_a = a, fixed_b = b;
  if (sleeper) (sleeper == &a ? fixed_a : fixed_b).mass *= 1e12;
  std::array<Eigen::Vector3d, 4> impulses;
  const auto solve = [&](const Body& x, const Body& y) {
    for (int k = 0; k < n; ++k) impulses[std::size_t(k)] = pair_impulse(x, y, at(k), c.normal, m) / n;
  };
  solve(fixed_a, fixed_b);
  if (sleeper) {
    double normal = 0;
    for (int k = 0; k < n; ++k) normal += std::abs(impulses[std::size_t(k)].dot(c.normal));
    const double weight = awake->mass * std::abs(spec_.gravity.dot(c.normal)) * dt;
    if (impact || normal > 1.5 * weight + awake->mass * spec_.sleep_speed) {
      sleeper->sleeping = false, sleeper->still_s = 0;
      sleeper = nullptr;
      solve(a, b);
    }
  }
  bool moved = false;
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d& P = impulses[std::size_t(k)];
    if (P.isZero()) continue;
    if (sleeper != &b) b.v += P / b.mass, b.w += (at(k) - b.x).cross(P) / inertia(b);
    if (sleeper != &a) a.v -= P / a.mass, a.w -= (at(k) - a.x).cross(P) / inertia(a);
    moved = true;
  }
  r.touches += first && moved;
  if (first && c.depth > 0) {
    const double share = sleeper ? (sleeper == &b ? 1.0 : 0.0) : b.mass / (a.mass + b.mass);
    const double undo = (impact ? 1 : kRestingUndo) * c.depth;
    a.x -= share * undo * c.normal;
    b.x += (1 - share) * undo * c.normal;
  }
  return true;
}

StepReport World::step(double dt) {
  if (!(dt > 0 && std::isfinite(dt))) throw std::invalid_argument("rigid: dt must be > 0");
  StepReport r;
  for (Body& b : bodies_) hit(b, dt, r);
  const Drag& d = spec_.drag;
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body& b = bodies_[i];
    const Load& l = loads_[i];
    if (!l.force.isZero() || !l.torque.isZero()) b.sleeping = false, b.still_s = 0;
    if (b.sleeping) continue;
    b.v += (spec_.gravity + l.force / b.mass) * dt;
    b.w += l.torque / inertia(b) * dt;
    // Drag, implicit in its coefficient: it slows, never reverses.
    b.v /= 1 + dt * (d.linear + d.quadratic * b.v.norm()) / b.mass;
    b.w /= 1 + dt * (d.angular_linear + d.angular_quadratic * b.w.norm()) / inertia(b);
  }
  // Contacts between bodies, then with the plane; where bodies touch, the
  // passes repeat (Gauss-Seidel), so that a body resting on another that
  // rests on the plane is held by both (one pass would let the top one
  // sink a little every step and never sleep).
  bool touching = false;
  for (int pass = 0; pass == 0 || (touching && pass < kContactPasses); ++pass) {
    for (std::size_t i = 0; i < bodies_.size(); ++i)
      for (std::size_t j = i + 1; j < bodies_.size(); ++j)
        touching = touch(bodies_[i], bodies_[j], pass == 0, dt, r) || touching;
    if (spec_.ground)
      for (Body& b : bodies_)
        if (!b.sleeping) floor(b, dt);
  }
  for (std::size_t i = 0; i < bodies_.size(); ++i) {
    Body& b = bodies_[i];
    if (b.sleeping) continue;
    ++r.simulated;
    b.x += b.v * dt;
    b.q = (rotation(b.w, dt) * b.q).normalized();
    if (spec_.ground) {
      double low = 0;
      const Support s = support_points(b);
      for (int k = 0; k < s.n; ++k) low = std::min(low, s.p[std::size_t(k)].z());
      b.x.z() -= low;  // out of the plane
    }
    const bool loaded = !loads_[i].force.isZero() || !loads_[i].torque.isZero();
    const bool slow = !loaded && b.v.norm() < spec_.sleep_speed && b.w.norm() * b.size < spec_.sleep_speed;
    b.still_s = slow ? b.still_s + dt : 0;
    if (b.still_s >= spec_.sleep_time) b.sleeping = true, b.v.setZero(), b.w.setZero();
  }
  tip_.x += tip_.v * dt;
  return r;
}

Eigen::Vector3d World::momentum() const {
  Eigen::Vector3d p = spec_.tip_mass * tip_.v;
  for (const Body& b : bodies_) p += models::rigid::momentum(b);
  return p;
}

Eigen::Vector3d World::angular_momentum() const {
  Eigen::Vector3d l = spec_.tip_mass * tip_.x.cross(tip_.v);
  for (const Body& b : bodies_) l += models::rigid::angular_momentum(b);
  return l;
}

double World::kinetic_energy() const {
  double e = 0.5 * spec_.tip_mass * tip_.v.squaredNorm();
  for (const Body& b : bodies_) e += models::rigid::kinetic_energy(b);
  return e;
}

}  // namespace hcosim::models::rigid
