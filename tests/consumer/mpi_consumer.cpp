// A research code's task farm against the installed libdem::mpi: over MPI ranks under mpirun,
// else this process alone. Prints the sum of the squares 0..9, which every process computes the
// same way whoever ran each task.
#include <cstdio>
#include <memory>
#include <string>

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
}
