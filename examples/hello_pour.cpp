// The smallest complete libdem program: pours a polydisperse packing into a box under gravity and
// prints the kinetic energy as it settles.
#include <cstdio>
#include <random>

#include <dem/dem.hpp>

int main() {
  using namespace dem;
  WorldSettings settings;
  settings.gravity = Vec3(0, 0, -9.81);  // m/s^2
  settings.local_damping = 0.3;          // some damping, so that the pile comes to rest
  World world(settings);

  // 600 balls of 0.8-1.2 mm diameter on a lattice above a 12 mm x 12 mm box, with a random jitter.
  std::mt19937_64 rng(42);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int k = 0; k < 600; ++k) {
    BallSpec ball;
    ball.position = Vec3(-4.5e-3 + 1.3e-3 * (k % 8), -4.5e-3 + 1.3e-3 * (k / 8 % 8), 1e-3 + 1.3e-3 * (k / 64));
    ball.position += Vec3(unit(rng), unit(rng), unit(rng)) * 5e-5;
    ball.radius = 0.4e-3 + 0.2e-3 * unit(rng);  // m
    ball.density = 2650.0;                      // kg/m^3, quartz
    world.add_ball(ball);
  }

  // An open box of facet walls: floor and four sides; outward normals point away from the sand.
  const double h = 6e-3;
  world.add_wall(make_facet_wall("floor", geometry::make_rectangle(Vec3(0, 0, 0), Vec3(h, 0, 0), Vec3(0, h, 0)), -Vec3::UnitZ()));
  for (const Vec3& n : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)}) {
    const Vec3 along = n.cross(Vec3::UnitZ()) * h;
    world.add_wall(make_facet_wall("side", geometry::make_rectangle(n * h + Vec3(0, 0, 8e-3), along, Vec3(0, 0, 8e-3)), n));
  }

  // Rolling-resistance linear contacts from an effective modulus (Pa), stiffness ratio, mu, mu_r.
  const auto sand = RollingLinearLaw::Params::deformable(5e7, 1.0, 0.5, 0.2);
  world.set_contact_model(ContactKind::BallBall, make_contact_model<RollingLinearLaw>(sand, "ball-ball"));
  world.set_contact_model(ContactKind::BallFacet, make_contact_model<RollingLinearLaw>(sand, "ball-facet"));

  std::printf("%10s %12s %14s %10s\n", "step", "time [s]", "kinetic [J]", "contacts");
  for (int block = 0; block <= 20; ++block) {
    std::printf("%10lld %12.5f %14.6e %10zu\n", static_cast<long long>(world.step_count()), world.time(),
                world.kinetic_energy(), world.contact_count(ContactKind::BallBall));
    world.step(2000);
  }
  std::printf("time step %.3e s; the pile has settled when the kinetic energy has dropped by decades\n",
              world.time_step());
}
