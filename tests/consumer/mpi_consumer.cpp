// A research code against the installed libdem::mpi: a task farm over MPI ranks under mpirun, else
// this process alone, and a World spread over the same ranks. Prints the sum of the squares 0..9,
// which every process computes the same way whoever ran each task, and the speeds of two equal
// balls after a head-on elastic collision, which exchange their velocities (1 and 0 m/s).
#include <cstdio>
#include <memory>
#include <string>

#include <dem/dem.hpp>
#include <dem/parallel/mpi_domains.hpp>
#include <dem/parallel/mpi_farm.hpp>

int main(int argc, char** argv) {
  std::unique_ptr<dem::parallel::TaskFarm> farm;
  if (dem::parallel::launched_ranks() != 0) farm = std::make_unique<dem::parallel::MpiFarm>(argc, argv);
  else farm = std::make_unique<dem::parallel::LocalFarm>();
  long sum = 0;
  farm->run(
      10, 1, [](std::size_t i) { return std::to_string(i * i); },
      [&](std::size_t, const std::string& square) { sum += std::stol(square); });
  if (farm->leads()) std::printf("farm of %d: sum of squares %ld\n", farm->processes(), sum);

  dem::WorldSettings settings;
  settings.local_damping = 0.0;
  settings.time_step = 1e-7;
  dem::World world(settings);
  for (double x : {0.0, 3e-3}) world.add_ball({.position = dem::Vec3(x, 0, 0), .radius = 1e-3, .density = 2650.0,
                                               .velocity = dem::Vec3(x == 0.0 ? 1.0 : 0.0, 0, 0)});
  world.set_contact_model(dem::ContactKind::BallBall, dem::make_contact_model<dem::LinearLaw>(
                                                          dem::LinearLaw::Params::constant(1e5, 1e5, 0.0), "ball-ball"));
  if (auto* mpi = dynamic_cast<dem::parallel::MpiFarm*>(farm.get()))
    world.spread_over(std::make_shared<dem::parallel::MpiDomains>(*mpi));
  world.step(20000);  // 2 ms: 1 mm of approach, a contact of about 0.1 ms, and apart again
  const auto& p = world.particles();
  if (farm->leads()) std::printf("collision: speeds %.3f %.3f m/s\n", p.v[p.index_of(0)].x(), p.v[p.index_of(1)].x());
}
