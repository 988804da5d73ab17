// Measurement sphere (docs/model.md 6, test T9): stress of a compressed simple-cubic lattice in both
// forms, lattice porosity, the stress inside a relaxed packing against the wall stress, the strain
// rate of an imposed uniform velocity gradient, and bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include <dem/measure/measurement_sphere.hpp>

#include "support/scenes.hpp"

using namespace dem;
using namespace dem::testing;
using Catch::Matchers::Contains;

namespace {

/// Simple-cubic lattice of fixed balls of radius r, spacing s, centres s (i, j, k) with
/// |i|, |j|, |k| <= half_count.
void add_lattice(World& world, double r, double s, int half_count) {
  for (int i = -half_count; i <= half_count; ++i)
    for (int j = -half_count; j <= half_count; ++j)
      for (int k = -half_count; k <= half_count; ++k) {
        BallSpec b = ball_at(Vec3(i * s, j * s, k * s), Vec3::Zero(), r);
        b.fixed = dof_all;
        world.add_ball(b);
      }
}

/// Lattice points s (i, j, k) + offset inside the sphere: an independent count of the contact
/// points of one axis.
int count_inside(const MeasurementSphere& sphere, double s, int half_count, const Vec3& offset) {
  int count = 0;
  for (int i = -half_count; i <= half_count; ++i)
    for (int j = -half_count; j <= half_count; ++j)
      for (int k = -half_count; k <= half_count; ++k)
        if ((Vec3(i * s, j * s, k * s) + offset - sphere.centre).norm() <= sphere.radius) ++count;
  return count;
}

double max_off_diagonal(const Mat3& m) {
  return std::max({std::abs(m(0, 1)), std::abs(m(0, 2)), std::abs(m(1, 2)), std::abs(m(1, 0)),
                   std::abs(m(2, 0)), std::abs(m(2, 1))});
}

// Relative error bound of the solid fraction a sphere of radius r measures in a simple-cubic
// lattice of spacing s with exact ball-sphere volumes. By Poisson summation the error is
// sum_{k != 0} S^(k) B^(k) / (V_S V_B) over the reciprocal lattice (S^, B^: Fourier transforms of
// the sphere and ball indicators); bounding |sin x - x cos x| <= sqrt(1 + x^2) in S^ and summing
// numerically gives 0.251 (s/r)^2 for 2R = s (0.139 (s/r)^2 from the 6 nearest vectors alone).
double lattice_solid_fraction_bound(double s, double r) { return 0.26 * (s / r) * (s / r); }

}  // namespace

TEST_CASE("measurement sphere: T9 compressed simple-cubic lattice", "[physics][measure-sphere]") {
  const double r = radius, delta = 1e-3 * 2 * r, s = 2 * r - delta;  // m
  const double kn = 1e5;                                             // N/m
  const double force = kn * delta;                                    // 0.1 N per contact
  const int half_count = 10;
  World world(dynamic_settings(1e-7));
  add_lattice(world, r, s, half_count);
  const auto law = make_contact_model<LinearLaw>(LinearParams::constant(kn, kn, 0.5), "ball-ball");
  world.set_contact_model(ContactKind::BallBall, law);
  world.step();

  // A centre off every lattice symmetry, so no count is equal by luck; radius 8 s keeps the
  // sphere and its contact points two spacings inside the 21^3 lattice.
  const MeasurementSphere sphere{Vec3(0.31, 0.17, 0.43) * s, 8 * s};
  const SphereMeasurement m = measure::measure(world, sphere);
  const double expected = -force / (s * s);  // Pa, -1.002e5

  // Ball-based form: every ball inside has its six contacts, so sigma_ii = -(1 - n) F s / V_b;
  // the only error is the measured solid fraction's (bound above, 0.41 % here).
  const double tol_ball = lattice_solid_fraction_bound(s, sphere.radius);
  for (int a = 0; a < 3; ++a) CHECK(m.stress(a, a) == Approx(expected).epsilon(tol_ball));
  // The three axes see the same balls: equal to round-off.
  CHECK(m.stress(0, 0) == Approx(m.stress(1, 1)).epsilon(1e-12));
  CHECK(m.stress(0, 0) == Approx(m.stress(2, 2)).epsilon(1e-12));
  // Forces and branches are along the axes and the lattice coordinates are exact in y and z of an
  // x-contact: off-diagonal moments vanish to round-off.
  CHECK(max_off_diagonal(m.stress) <= 1e-12 * std::abs(expected));

  // Overlaps between balls count twice (docs/model.md 6.2), so the solid fraction is V_b / s^3.
  const double solid_fraction = 4.0 / 3.0 * pi * r * r * r / (s * s * s);  // 0.525172
  CHECK(m.porosity == Approx(1.0 - solid_fraction).margin(solid_fraction * tol_ball));

  // Contact-based form: sigma_aa = -N_a F s / V_S, where N_a counts the contact points of axis a
  // inside (counted here independently), so it must match to round-off...
  const double sphere_volume = 4.0 / 3.0 * pi * std::pow(sphere.radius, 3);
  int total = 0;
  for (int a = 0; a < 3; ++a) {
    Vec3 offset = Vec3::Zero();
    offset[a] = 0.5 * s;
    const int count = count_inside(sphere, s, half_count, offset);
    total += count;
    CHECK(m.stress_contacts(a, a) == Approx(-count * force * s / sphere_volume).epsilon(1e-9));
    // ...and -F/s^2 within the lattice-point counting noise (Gauss's sphere problem), which over
    // random centres at r = 8 s stays below 0.5 %; 2 % leaves room and still catches a missing
    // factor or a half-counted contact set.
    CHECK(m.stress_contacts(a, a) == Approx(expected).epsilon(0.02));
  }
  CHECK(max_off_diagonal(m.stress_contacts) <= 1e-12 * std::abs(expected));

  // Contact statistics of the lattice: six contacts per ball, fabric from the axis counts.
  CHECK(m.contacts == static_cast<std::size_t>(total));
  CHECK(m.coordination_number == 6.0);
  CHECK(m.mechanical_coordination_number == 6.0);
  CHECK(m.fabric(0, 0) == Approx(static_cast<double>(count_inside(sphere, s, half_count, Vec3(0.5 * s, 0, 0))) /
                                  total).epsilon(1e-12));
  CHECK(m.fabric.trace() == Approx(1.0).epsilon(1e-12));
  CHECK(max_off_diagonal(m.fabric) == 0.0);
  // A hydrostatic compression: sigma_1 = sigma_3 = F/s^2 (compression positive).
  CHECK(m.principal.sigma_1 == Approx(-m.stress(0, 0)).epsilon(1e-12));
  CHECK(m.principal.sigma_3 == Approx(-m.stress(0, 0)).epsilon(1e-12));
  // Fixed balls at rest: no deformation rate.
  CHECK(m.strain_rate.cwiseAbs().maxCoeff() == 0.0);
}

TEST_CASE("measurement sphere: lattice porosity converges to 1 - pi/6", "[physics][measure-sphere]") {
  const double s = 2 * radius;  // undeformed lattice, touching balls
  const int half_count = 10;
  World world(dynamic_settings(1e-7));
  add_lattice(world, radius, s, half_count);
  const double exact = 1.0 - pi / 6.0;  // 0.476401
  for (double r_sphere : {3 * s, 5 * s, 8 * s}) {
    const MeasurementSphere sphere{Vec3(0.31, 0.17, 0.43) * s, r_sphere};
    const SphereMeasurement m = measure::measure(world, sphere);
    // Absolute porosity error = solid fraction pi/6 times its relative error bound (see above):
    // 0.0152 at 3 s, 0.0055 at 5 s, 0.0021 at 8 s.
    CHECK(m.porosity == Approx(exact).margin(pi / 6 * lattice_solid_fraction_bound(s, r_sphere)));
  }
}

TEST_CASE("measurement sphere: lens volume of two spheres", "[physics][measure-sphere]") {
  const double r = 2e-3;  // m
  using measure::sphere_intersection_volume;
  // Equal spheres one radius apart: two caps of height r/2, 5 pi r^3 / 12.
  CHECK(sphere_intersection_volume(r, r, r) == Approx(5.0 * pi * r * r * r / 12.0).epsilon(1e-14));
  CHECK(sphere_intersection_volume(r, 0.5 * r, 0.2 * r) == Approx(4.0 / 3.0 * pi * std::pow(0.5 * r, 3)).epsilon(1e-14));
  CHECK(sphere_intersection_volume(r, 0.5 * r, 1.5 * r) == 0.0);
  // Continuous where one sphere starts to contain the other (d = r1 - r2).
  CHECK(sphere_intersection_volume(r, 0.5 * r, 0.5 * r * (1 + 1e-9)) ==
        Approx(4.0 / 3.0 * pi * std::pow(0.5 * r, 3)).epsilon(1e-8));
  CHECK_THROWS_AS(sphere_intersection_volume(r, r, -1e-3), InputError);
}

namespace {

/// Cube |x|, |y|, |z| <= half of six frictionless facet walls, ordered -x, +x, -y, +y, -z, +z.
/// The rectangles reach past the edges so that no ball meets a wall's rim; each wall's loaded
/// area is the face of the cube.
void add_cube(World& world, double half) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side : {-1, 1}) {
      Vec3 n = Vec3::Zero(), u = Vec3::Zero(), v = Vec3::Zero();
      n[axis] = side;
      u[(axis + 1) % 3] = 1.5 * half;
      v[(axis + 2) % 3] = 1.5 * half;
      world.add_wall(make_facet_wall("cube", geometry::make_rectangle(n * half, u, v), n, 4 * half * half));
    }
}

/// 2000 balls in the cube, compressed to an isotropic state and relaxed (see the test below).
/// Returns the largest final radius, m.
double compressed_packing(World& world, double half) {
  const double r_min = 0.15e-3, r_max = 0.2e-3;  // m, drawn radii, grown about 2.4x
  double solid = 0.0;                             // m^3
  for (BallSpec b : separated_balls(2000, 2 * half - 2 * r_max, r_min, r_max, 1)) {
    b.position -= Vec3::Constant(half - r_max);
    solid += 4.0 / 3.0 * pi * std::pow(b.radius, 3);
    world.add_ball(b);
  }
  add_cube(world, half);
  auto ball_ball = [](double friction) {
    return make_contact_model<LinearLaw>(LinearParams::deformable(modulus_ball, 1.0, friction), "ball-ball");
  };
  world.set_contact_model(ContactKind::BallBall, ball_ball(0.0));
  world.set_contact_model(ContactKind::BallFacet,
                          make_contact_model<LinearLaw>(LinearParams::deformable(modulus_wall, 1.0, 0.0), "ball-facet"));
  // Radius expansion (docs/model.md 7) to a solid fraction of 0.65, above random close packing, so the
  // packing ends up compressed everywhere. Frictionless while it jams: a frictional packing
  // jams loose and keeps the heterogeneity of its assembly; friction then stops the slow creep
  // of the frictionless packing, and the state relaxes within a few hundred steps.
  const int blocks = 200;
  const double growth = std::pow(std::cbrt(0.65 * std::pow(2 * half, 3) / solid), 1.0 / blocks);
  ParticleStore& p = world.particles();
  for (int k = 0; k < blocks; ++k) {
    for (std::size_t i = 0; i < p.size(); ++i) p.set_radius(i, p.radius[i] * growth);
    world.invalidate_contacts();
    world.update_time_step();
    world.step(10);
  }
  world.step(1000);
  world.set_contact_model(ContactKind::BallBall, ball_ball(0.3));
  world.run_until([](const World& w) { return w.unbalanced_force_ratio() < 1e-5; }, 200, 4000);
  return r_max * std::pow(growth, blocks);
}

}  // namespace

TEST_CASE("measurement sphere: stress inside a compressed random packing", "[physics][measure-sphere]") {
  const double half = 5e-3;  // m
  World world;               // local damping 0.7, automatic time step
  const double d_max = 2 * compressed_packing(world, half);  // 0.97 mm, box = 10.3 d_max
  REQUIRE(world.unbalanced_force_ratio() < 1e-5);  // static: the averaging theorem below applies
  const auto& walls = world.walls();

  {
    // Love's averaging theorem. A sphere around the whole specimen holds every ball wholly, so
    // (1 - n) / sum V_b = 1 / V_S and both forms give (contact moment) / V_S. In equilibrium that
    // moment is the moment of the wall forces, so sigma V_S / V_box is the wall stress tensor:
    // on the diagonal, minus the mean normal stress of the two walls across that axis.
    const MeasurementSphere all{Vec3::Zero(), 2 * half};
    const SphereMeasurement m = measure::measure(world, all);
    CHECK(m.balls == world.particles().size());
    const double to_box = (4.0 / 3.0 * pi * std::pow(all.radius, 3)) / std::pow(2 * half, 3);
    // Wall contact points sit half an overlap beyond the wall planes (x_c is mid-overlap), which
    // lengthens the lever arm by delta / (2 half); the residual imbalance adds ~1e-5.
    double max_wall_overlap = 0.0;  // m
    world.for_each_contact([&](const ContactView& c) {
      if (c.kind == ContactKind::BallFacet)
        max_wall_overlap = std::max(
            max_wall_overlap, 2 * (world.particles().radius[c.first] - (c.point - world.particles().x[c.first]).norm()));
    });
    const double tol = max_wall_overlap / (2 * half) + 1e-3;
    for (int a = 0; a < 3; ++a) {
      const double wall_stress = 0.5 * (walls[2 * a].normal_stress() + walls[2 * a + 1].normal_stress());
      CHECK(-m.stress(a, a) * to_box == Approx(wall_stress).epsilon(tol));
      CHECK(-m.stress_contacts(a, a) * to_box == Approx(wall_stress).epsilon(tol));
    }
  }

  {
    // An interior sphere sees the isotropic wall stress.
    const MeasurementSphere sphere{Vec3::Zero(), half - d_max};  // ~580 balls, one d_max from the walls
    const SphereMeasurement m = measure::measure(world, sphere);
    const double top = walls[5].normal_stress();  // Pa, compression positive
    // Random packings are looser against flat walls, so the wall-parallel stress of the boundary
    // layers is lower and the interior carries more than the wall average: 3-9 % in eight
    // packings made this way (2000 and 4000 balls), 2.6 % in this one. That bounds what any
    // interior sphere can match; 12 % still catches a lost porosity factor (~32 %) or a wrong
    // volume.
    CHECK(-m.stress(2, 2) == Approx(top).epsilon(0.12));
    // The two forms weigh the cut balls and contacts at the sphere's surface differently; the
    // sampling noise of that shell is a few % of the whole (see below).
    CHECK(m.stress.trace() == Approx(m.stress_contacts.trace()).epsilon(0.05));

    // Isotropy: an isotropic sample of N contacts with weights w = F l (l varies little here, so
    // w's spread is that of the normal forces) has a deviator of
    // Frobenius norm ~ p sqrt(6 (1 + CV_w^2) / N); the principal spread is at most sqrt(2) times
    // that norm, and twice the rms norm bounds it with 99.9 % probability (chi-square, 5 dof).
    const auto samples = measure::ball_contacts_inside(world, sphere);
    REQUIRE(samples.size() == m.contacts);
    double sum = 0.0, sum_sq = 0.0;
    for (const auto& c : samples) sum += c.normal_force, sum_sq += c.normal_force * c.normal_force;
    const double n = static_cast<double>(samples.size());  // ~2100
    const double cv_sq = sum_sq * n / (sum * sum) - 1.0;
    const double spread_bound = 2.0 * std::sqrt(2.0) * std::sqrt(6.0 * (1.0 + cv_sq) / n);  // ~0.18
    const double mean = (m.principal.sigma_1 + m.principal.sigma_2 + m.principal.sigma_3) / 3.0;
    CHECK((m.principal.sigma_1 - m.principal.sigma_3) / mean < spread_bound);
    // The sphere sits one d_max from the walls: no facet contact inside, so the coordination
    // number counts ball-ball contacts, each shared by two balls.
    CHECK(m.coordination_number > 6.0);  // compressed beyond isostatic frictionless jamming (6)
  }
}

TEST_CASE("measurement sphere: strain rate of an imposed uniform velocity gradient", "[physics][measure-sphere]") {
  Mat3 gradient;  // 1/s, not symmetric: its spin part must drop out
  gradient << 1.0, 2.0, -0.5, 0.3, -1.0, 0.7, -2.0, 0.1, 0.4;
  const Vec3 drift(0.01, -0.02, 0.005);  // m/s, uniform translation, must drop out
  World world(dynamic_settings(1e-7));
  for (BallSpec b : separated_balls(300, 6e-3, 0.2e-3, 0.3e-3, 3)) {
    b.position += Vec3(1e-2, -2e-2, 3e-2);  // away from the origin: the means must be removed
    b.velocity = drift + gradient * b.position;
    b.fixed = dof_all;
    world.add_ball(b);
  }
  const MeasurementSphere sphere{Vec3(1.3e-2, -1.7e-2, 3.3e-2), 2.5e-3};
  const SphereMeasurement m = sphere.measure(world);  // the member spelling of measure::measure
  REQUIRE(m.balls > 20);
  const Mat3 expected = 0.5 * (gradient + gradient.transpose());
  // The least-squares fit of an exactly linear field is exact; round-off in the centred sums is
  // ~1e-16 relative to |x| ~ 4e-2 m over spreads ~2e-3 m: 1e-12 of |L| is ample.
  CHECK((m.strain_rate - expected).cwiseAbs().maxCoeff() < 1e-12 * gradient.norm());
  // Balls not touching: no stress, no contacts, no fabric.
  CHECK(m.stress.isZero(0.0));
  CHECK(m.coordination_number == 0.0);
  CHECK(m.contacts == 0);
  CHECK(std::isnan(m.fabric(0, 0)));

  // Three balls, or balls in one plane, do not determine a 3-D gradient: NaN, not garbage.
  World flat(dynamic_settings(1e-7));
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) flat.add_ball(ball_at(Vec3(i * 1e-3, j * 1e-3, 0.0), Vec3(1e-3 * i, 0, 0)));
  CHECK(std::isnan(measure::measure(flat, {Vec3(2e-3, 2e-3, 0), 5e-3}).strain_rate(0, 0)));
  CHECK(std::isnan(measure::measure(flat, {Vec3::Zero(), 1.2e-3}).strain_rate(0, 0)));  // 3 balls
}

TEST_CASE("measurement sphere: bad input", "[physics][measure-sphere]") {
  World world(dynamic_settings(1e-7));
  world.add_ball(ball_at(Vec3::Zero()));
  CHECK_THROWS_WITH(measure::measure(world, {Vec3::Zero(), 0.0}), Contains("radius") && Contains("= 0"));
  CHECK_THROWS_WITH(measure::measure(world, {Vec3::Zero(), -1e-3}), Contains("radius") && Contains("-0.001"));
  CHECK_THROWS_AS(measure::measure(world, {Vec3::Zero(), std::nan("")}), InputError);
  CHECK_THROWS_AS(measure::measure(world, {Vec3::Zero(), HUGE_VAL}), InputError);
  CHECK_THROWS_WITH(measure::measure(world, {Vec3(std::nan(""), 0, 0), 1e-3}), Contains("centre") && Contains("nan"));
  CHECK_THROWS_WITH(measure::measure(world, {Vec3(1.0, 0, 0), 1e-3}),
                    Contains("ball centres inside") && Contains("radius 0.001"));
  CHECK_THROWS_AS(measure::ball_contacts_inside(world, {Vec3::Zero(), -1.0}), InputError);
  CHECK_THROWS_WITH(MeasurementSphere({Vec3::Zero(), 0.0}).validate("probe"), Contains("probe.radius"));
  // A sphere that holds only part of a ball, but its centre, is valid.
  CHECK(measure::measure(world, {Vec3(0.5 * radius, 0, 0), 0.6 * radius}).balls == 1);
}
