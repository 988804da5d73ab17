// Measurement sphere (docs/model.md 6.1, 6.2). One pass over the particles marks the balls inside and
// accumulates volumes and velocity moments; one pass over the contacts accumulates both stress
// sums, contact counts and fabric samples.
//
// Positions enter relative to the sphere centre: the moment sums then stay of the size of the
// sphere, not of the world coordinates, which keeps the centred second moments free of
// cancellation.
#include <dem/measure/measurement_sphere.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Eigenvalues>

#include <dem/base/errors.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/core/world.hpp>

namespace dem {

void MeasurementSphere::validate(const std::string& where) const {
  if (!centre.allFinite()) {
    std::ostringstream value;
    value << "(" << centre.x() << ", " << centre.y() << ", " << centre.z() << ")";
    require(false, where + ".centre", value.str(), "finite (m)");
  }
  require(radius > 0.0 && std::isfinite(radius), where + ".radius", radius, "finite and > 0 (m)");
}

namespace measure {
namespace {

constexpr double not_a_number = std::numeric_limits<double>::quiet_NaN();

// Below this ratio of smallest to largest eigenvalue of sum x~ x~^T the balls are taken as not
// spanning 3-D: rounding is ~1e-16, a real packing gives ~1, a flat layer gives ~1e-16 or less.
constexpr double degenerate_spread = 1e-10;

double lens_volume(double r1, double r2, double d) {
  if (d >= r1 + r2) return 0.0;
  const double smaller = std::min(r1, r2);
  if (d <= std::abs(r1 - r2)) return 4.0 / 3.0 * pi * smaller * smaller * smaller;
  // Two spherical caps: pi (r1 + r2 - d)^2 (d^2 + 2 d (r1 + r2) - 3 (r1 - r2)^2) / (12 d).
  const double gap = r1 + r2 - d;
  return pi * gap * gap * (d * d + 2.0 * d * (r1 + r2) - 3.0 * (r1 - r2) * (r1 - r2)) / (12.0 * d);
}

Mat3 symmetric_part(const Mat3& m) { return 0.5 * (m + m.transpose()); }

bool inside(const MeasurementSphere& s, const Vec3& x) { return (x - s.centre).squaredNorm() <= s.radius * s.radius; }

}  // namespace

double sphere_intersection_volume(double r1, double r2, double distance) {
  for (double v : {r1, r2, distance})
    require(v >= 0.0 && std::isfinite(v), "sphere_intersection_volume argument", v, "finite and >= 0 (m)");
  return lens_volume(r1, r2, distance);
}

std::vector<ContactSample> ball_contacts_inside(const World& world, const MeasurementSphere& sphere) {
  sphere.validate();
  std::vector<ContactSample> samples;
  world.for_each_contact([&](const ContactView& c) {
    if (c.kind == ContactKind::BallBall && inside(sphere, c.point)) samples.push_back({c.normal, c.normal_force});
  });
  return samples;
}

SphereMeasurement measure(const World& world, const MeasurementSphere& sphere) {
  sphere.validate();
  const ParticleStore& p = world.particles();
  const std::size_t n = p.size();
  SphereMeasurement out;

  // --- particles: membership, volumes, velocity moments ----------------------------------------
  std::vector<char> is_inside(n, 0);
  double ball_volume = 0.0;   // m^3, whole volumes of the balls inside
  double solid_volume = 0.0;  // m^3, parts of all balls inside the sphere
  Vec3 sum_x = Vec3::Zero(), sum_v = Vec3::Zero();
  Mat3 sum_xx = Mat3::Zero(), sum_vx = Mat3::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    if (p.is_pebble(i)) continue;
    const double r = p.radius[i];
    const Vec3 x = p.x[i] - sphere.centre;
    const double d = x.norm();
    if (d >= sphere.radius + r) continue;
    solid_volume += lens_volume(sphere.radius, r, d);
    if (d > sphere.radius) continue;
    is_inside[i] = 1;
    ++out.balls;
    ball_volume += 4.0 / 3.0 * pi * r * r * r;
    sum_x += x;
    sum_v += p.v[i];
    sum_xx += x * x.transpose();
    sum_vx += p.v[i] * x.transpose();
  }
  if (out.balls == 0) {
    std::ostringstream where;
    where << "measurement sphere at (" << sphere.centre.x() << ", " << sphere.centre.y() << ", "
          << sphere.centre.z() << ") m, radius " << sphere.radius << " m: number of ball centres inside";
    require(false, where.str(), 0, ">= 1 (place the sphere inside the specimen; lengths are in m)");
  }
  const double sphere_volume = 4.0 / 3.0 * pi * sphere.radius * sphere.radius * sphere.radius;
  out.porosity = 1.0 - solid_volume / sphere_volume;

  // --- contacts: both stress sums, counts, fabric ---------------------------------------------
  Mat3 ball_moment = Mat3::Zero();     // N m, sum_b sum_c (x_c - x_b) (outer) F_c^(b)
  Mat3 contact_moment = Mat3::Zero();  // N m, sum_{x_c in S} F_c (outer) L_c
  std::vector<int> contact_count(n, 0);
  std::vector<ContactSample> samples;
  world.for_each_contact([&](const ContactView& c) {
    const std::size_t b1 = c.first;
    const bool ball_ball = c.kind == ContactKind::BallBall;
    const auto b2 = static_cast<std::size_t>(c.second);  // a particle only for ball-ball and ball-pebble
    if (is_inside[b1]) {
      ball_moment -= (c.point - p.x[b1]) * c.force.transpose();  // ball 1 receives -F
      ++contact_count[b1];
    }
    if (ball_ball && is_inside[b2]) {
      ball_moment += (c.point - partner_position(p.x.data(), b1, b2, c.image_shift)) * c.force.transpose();
      ++contact_count[b2];
    }
    if (!inside(sphere, c.point)) return;
    const Vec3 branch_vector = ball_ball ? branch(p.x.data(), b1, b2, c.image_shift) : Vec3(c.point - p.x[b1]);
    contact_moment += c.force * branch_vector.transpose();
    if (ball_ball) samples.push_back({c.normal, c.normal_force});
  });

  out.stress = symmetric_part(ball_moment) * ((1.0 - out.porosity) / ball_volume);
  out.stress_contacts = symmetric_part(contact_moment) * (-1.0 / sphere_volume);
  out.principal = principal_stresses(out.stress);

  out.contacts = samples.size();
  out.fabric = samples.empty() ? Mat3::Constant(not_a_number) : fabric_tensor(samples);

  long contacts_of_balls = 0, contacts_of_active = 0, active_balls = 0;
  for (std::size_t i = 0; i < n; ++i) {
    if (!is_inside[i]) continue;
    contacts_of_balls += contact_count[i];
    if (contact_count[i] >= 2) contacts_of_active += contact_count[i], ++active_balls;
  }
  out.coordination_number = static_cast<double>(contacts_of_balls) / static_cast<double>(out.balls);
  out.mechanical_coordination_number =
      active_balls == 0 ? 0.0 : static_cast<double>(contacts_of_active) / static_cast<double>(active_balls);

  // --- strain rate: L = (sum v~ x~^T)(sum x~ x~^T)^-1 over the balls inside (docs/model.md 6.2) ------
  const double count = static_cast<double>(out.balls);
  const Vec3 mean_x = sum_x / count, mean_v = sum_v / count;
  const Mat3 spread = sum_xx - count * mean_x * mean_x.transpose();  // m^2
  const Mat3 velocity_spread = sum_vx - count * mean_v * mean_x.transpose();  // m^2/s
  const Eigen::SelfAdjointEigenSolver<Mat3> spread_eigen(spread, Eigen::EigenvaluesOnly);
  const Vec3 spread_values = spread_eigen.eigenvalues();  // ascending
  if (out.balls < 4 || !(spread_values(0) > degenerate_spread * spread_values(2))) {
    out.strain_rate = Mat3::Constant(not_a_number);
  } else {
    out.strain_rate = symmetric_part(velocity_spread * spread.inverse());
  }
  return out;
}

}  // namespace measure
}  // namespace dem
