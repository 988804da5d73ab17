#include "task_farm.hpp"

#include <ostream>

#include <dem/core/errors.hpp>

#ifdef LIBDEM_WITH_MPI
#include <dem/parallel/mpi_domains.hpp>
#include <dem/parallel/mpi_farm.hpp>
#endif

namespace dem::cli {

std::unique_ptr<parallel::TaskFarm> open_task_farm([[maybe_unused]] int& argc, [[maybe_unused]] char**& argv) {
  const int launched = parallel::launched_ranks();
  if (launched == 0) return std::make_unique<parallel::LocalFarm>();
#ifdef LIBDEM_WITH_MPI
  auto farm = std::make_unique<parallel::MpiFarm>(argc, argv);
  if (launched > 0 && farm->processes() != launched)
    throw InputError("the launcher started " + std::to_string(launched) + " tasks, but MPI sees " +
                     std::to_string(farm->processes()) + " rank(s) in this one: each would do the whole run (with srun, "
                     "give it the MPI plugin of this OpenMPI, e.g. srun --mpi=pmix)");
  return farm;
#else
  throw InputError("started by an MPI launcher, but built without MPI: run it without mpirun, or install libopenmpi-dev "
                   "(scripts/install-deps) and build again");
#endif
}

std::shared_ptr<parallel::DomainComm> open_domains([[maybe_unused]] parallel::TaskFarm& farm) {
#ifdef LIBDEM_WITH_MPI
  if (auto* mpi = dynamic_cast<parallel::MpiFarm*>(&farm); mpi && mpi->processes() > 1)
    return std::make_shared<parallel::MpiDomains>(*mpi);
#endif
  return nullptr;
}

void require_one_process(const std::string& program) {
  const int ranks = parallel::launched_ranks();
  if (ranks == 0 || ranks == 1) return;
  throw InputError(program + " runs in one process, and was started on " +
                   (ranks > 0 ? std::to_string(ranks) : std::string("several")) +
                   " MPI ranks (each would run it whole in the same folder): run it without mpirun; over MPI ranks, "
                   "dem-simple-shear and dem-consolidate spread one simulation, dem-ensemble runs seeds and dem-calibrate "
                   "runs trials");
}

int end_on_error(parallel::TaskFarm& farm, const std::string& program, const std::exception& error, int code,
                 std::ostream& err) {
  if (farm.processes() == 1 || farm.failed_together()) {
    if (farm.leads()) err << program << ": " << error.what() << std::endl;
    return code;
  }
  err << program << " (rank " << farm.process() << " of " << farm.processes() << "): " << error.what() << std::endl;
#ifdef LIBDEM_WITH_MPI
  if (auto* mpi = dynamic_cast<parallel::MpiFarm*>(&farm)) mpi->abort_all(code);
#endif
  return code;
}

}  // namespace dem::cli
