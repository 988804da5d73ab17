#include <dem/boundary/clump.hpp>

#include <string>

#include <dem/base/errors.hpp>

namespace dem {

ClumpSpec& ClumpSpec::with_pebble_mass(double density) {
  require_positive("clump density", density);
  mass = 0.0;
  Vec3 moment = Vec3::Zero();
  for (const PebbleSpec& p : pebbles) {
    const double m = density * 4.0 / 3.0 * pi * p.radius * p.radius * p.radius;
    mass += m;
    moment += m * p.position;
  }
  centre_of_mass = mass > 0.0 ? Vec3(moment / mass) : Vec3::Zero();
  inertia.setZero();
  for (const PebbleSpec& p : pebbles) {
    const double m = density * 4.0 / 3.0 * pi * p.radius * p.radius * p.radius;
    const Vec3 r = p.position - centre_of_mass;
    // sphere about its centre plus the parallel-axis term
    inertia += (0.4 * m * p.radius * p.radius) * Mat3::Identity() + m * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
  }
  return *this;
}

void ClumpSpec::validate(const std::string& where) const {
  require(!pebbles.empty(), where + " pebble count", 0, "> 0");
  for (std::size_t k = 0; k < pebbles.size(); ++k) {
    require_positive(where + " pebble " + std::to_string(k) + " radius", pebbles[k].radius);
    require(pebbles[k].position.allFinite(), where + " pebble " + std::to_string(k) + " position", "(non-finite)",
            "finite");
  }
  require_positive(where + " mass", mass);
  require(inertia.allFinite() && (inertia - inertia.transpose()).norm() <= 1e-9 * inertia.norm(),
          where + " inertia", "(not symmetric)", "a symmetric tensor");
  require(inertia.ldlt().isPositive() && inertia.determinant() > 0.0, where + " inertia", "(not positive definite)",
          "positive definite");
}

}  // namespace dem
