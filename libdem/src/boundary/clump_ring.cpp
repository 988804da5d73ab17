// Ring stack builder (see clump_ring.hpp for the geometry). Counts are rounded with a relative
// slack of 1e-9 so that a spec whose numbers divide exactly (e.g. 7 rings of 1 mm in 7 mm) is not
// pushed to one more ring or pebble by round-off.
#include <dem/boundary/clump_ring.hpp>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>

#include <dem/base/errors.hpp>

namespace dem {

namespace {

constexpr double slack = 1e-9;       // -, relative round-off allowance in counts and checks
constexpr double max_pebbles = 1e7;  // a larger stack is a unit mistake, not a simulation

/// A length for a message: std::to_string would print 1e-5 m as 0.000010.
std::string show(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

void require_finite_positive(const std::string& name, double value) {
  require(std::isfinite(value) && value > 0.0, "ring stack " + name, value, "finite and > 0");
}

/// Rounds up, forgiving a relative excess of `slack` over an integer. Kept in double until the
/// pebble total is checked, so that absurd ratios cannot overflow an int.
double ceil_count(double x) { return std::ceil(x * (1.0 - slack)); }

struct Counts {
  int per_layer = 0;  // pebbles in one layer
  int layers = 0;     // layers in one ring
  int rings = 0;      // rings in the stack
};

/// Validates everything but max_opening and the height coverage (checked by make_ring_stack),
/// then counts pebbles, layers and rings.
Counts validated_counts(const RingStackSpec& s) {
  require(s.base_centre.allFinite(), "ring stack base_centre", "(non-finite)", "finite");
  require_finite_positive("inner_radius", s.inner_radius);
  require_finite_positive("height", s.height);
  require_finite_positive("pebble_radius", s.pebble_radius);
  require(s.ring_count >= 0, "ring stack ring_count", s.ring_count, ">= 0 (0: as many as cover the height)");
  require(std::isfinite(s.ring_height) && s.ring_height >= 2.0 * s.pebble_radius * (1.0 - slack),
          "ring stack ring_height", s.ring_height,
          "finite and >= the pebble diameter " + show(2.0 * s.pebble_radius) + " m");
  require(std::isfinite(s.gap) && s.gap >= 0.0, "ring stack gap", s.gap, "finite and >= 0");
  require_finite_positive("ring_density", s.ring_density);
  require(std::isfinite(s.max_opening) && s.max_opening >= 0.0, "ring stack max_opening", s.max_opening,
          "finite and >= 0 (0: no check)");
  require((s.fixed & ~dof_all) == 0, "ring stack fixed", static_cast<int>(s.fixed), "Dof bits (0..63)");

  // Chord 2 R sin(pi/n) <= r_peb on the circle R = a + r_peb of the pebble centres.
  const double per_layer = ceil_count(pi / std::asin(s.pebble_radius / (2.0 * (s.inner_radius + s.pebble_radius))));
  // Layer centres from r_peb above the ring's bottom to r_peb below its top, at most r_peb apart.
  const double span = s.ring_height - 2.0 * s.pebble_radius;
  const double layers = span <= slack * s.pebble_radius ? 1.0 : 1.0 + ceil_count(span / s.pebble_radius);
  const double rings = s.ring_count > 0 ? s.ring_count
                                        : std::max(1.0, ceil_count((s.height + s.gap) / (s.ring_height + s.gap)));
  require(per_layer * layers * rings <= max_pebbles, "ring stack pebble count", per_layer * layers * rings,
          "<= 1e7 (check the units of the radii and heights)");
  return {static_cast<int>(per_layer), static_cast<int>(layers), static_cast<int>(rings)};
}

double centre_radius(const RingStackSpec& s) { return s.inner_radius + s.pebble_radius; }

/// Largest ball diameter through the hole between two neighbouring pebbles of one layer and the
/// two above them, `vertical` (m) higher: the ball's centre passes radially through the middle of
/// the four centres, at sqrt((chord/2)^2 + (vertical/2)^2) from each.
double hole_diameter(double chord, double vertical, double pebble_radius) {
  return std::max(0.0, std::hypot(chord, vertical) - 2.0 * pebble_radius);
}

}  // namespace

RingMass thick_ring_mass(double inner, double outer, double height, double density) {
  require(std::isfinite(inner) && inner >= 0.0, "ring inner radius", inner, "finite and >= 0");
  require(std::isfinite(outer) && outer > inner, "ring outer radius", outer,
          "finite and > the inner radius " + show(inner) + " m");
  require(std::isfinite(height) && height > 0.0, "ring height", height, "finite and > 0");
  require(std::isfinite(density) && density > 0.0, "ring density", density, "finite and > 0");
  RingMass m;
  const double sum_sq = inner * inner + outer * outer;
  m.mass = density * pi * (outer * outer - inner * inner) * height;
  m.axial_inertia = m.mass * sum_sq / 2.0;
  m.radial_inertia = m.mass * (3.0 * sum_sq + height * height) / 12.0;
  return m;
}

int ring_pebble_count(const RingStackSpec& spec) { return validated_counts(spec).per_layer; }

int ring_layer_count(const RingStackSpec& spec) { return validated_counts(spec).layers; }

int ring_stack_count(const RingStackSpec& spec) { return validated_counts(spec).rings; }

double ring_stack_opening(const RingStackSpec& spec) {
  const Counts count = validated_counts(spec);
  const double r = spec.pebble_radius;
  const double chord = 2.0 * centre_radius(spec) * std::sin(pi / count.per_layer);
  double opening = std::max(0.0, chord - 2.0 * r);  // within a layer
  if (count.layers > 1)
    opening = std::max(opening, hole_diameter(chord, (spec.ring_height - 2.0 * r) / (count.layers - 1), r));
  if (count.rings > 1) opening = std::max(opening, hole_diameter(chord, 2.0 * r + spec.gap, r));
  return opening;
}

std::vector<ClumpSpec> make_ring_stack(const RingStackSpec& spec) {
  const Counts count = validated_counts(spec);
  const double covered = count.rings * spec.ring_height + (count.rings - 1) * spec.gap;
  require(covered >= spec.height * (1.0 - slack), "ring stack ring_count", count.rings,
          "enough rings to cover the height " + show(spec.height) + " m (they cover " + show(covered) +
              " m; use 0 to choose the count)");
  const double opening = ring_stack_opening(spec);
  if (spec.max_opening > 0.0)
    require(opening < spec.max_opening, "ring stack max_opening", spec.max_opening,
            "larger than the widest opening between pebbles, " + show(opening) + " m (a smaller gap narrows it)");

  const double r = spec.pebble_radius;
  const double radius = centre_radius(spec);
  const double layer_step = count.layers > 1 ? (spec.ring_height - 2.0 * r) / (count.layers - 1) : 0.0;
  const RingMass solid = thick_ring_mass(spec.inner_radius, spec.inner_radius + 2.0 * r, spec.ring_height,
                                         spec.ring_density);
  std::vector<ClumpSpec> stack;
  stack.reserve(static_cast<std::size_t>(count.rings));
  for (int k = 0; k < count.rings; ++k) {
    const double bottom = k * (spec.ring_height + spec.gap);  // m, above base_centre
    ClumpSpec ring;
    ring.pebbles.reserve(static_cast<std::size_t>(count.per_layer) * static_cast<std::size_t>(count.layers));
    for (int layer = 0; layer < count.layers; ++layer) {
      const double z = bottom + r + layer * layer_step;
      for (int j = 0; j < count.per_layer; ++j) {
        const double angle = 2.0 * pi * j / count.per_layer;
        ring.pebbles.push_back({spec.base_centre + Vec3(radius * std::cos(angle), radius * std::sin(angle), z), r});
      }
    }
    ring.mass = solid.mass;
    ring.centre_of_mass = spec.base_centre + Vec3(0.0, 0.0, bottom + 0.5 * spec.ring_height);
    ring.inertia = Vec3(solid.radial_inertia, solid.radial_inertia, solid.axial_inertia).asDiagonal();
    ring.fixed = spec.fixed;
    stack.push_back(std::move(ring));
  }
  return stack;
}

}  // namespace dem
