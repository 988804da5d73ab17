// The processes of an app's run: MPI ranks when an MPI launcher started it (and libdem::mpi was
// built), else this process alone; and how an app ends on an error when it runs on several.
#pragma once

#include <exception>
#include <iosfwd>
#include <memory>
#include <string>

#include <dem/parallel/domain_comm.hpp>
#include <dem/parallel/task_farm.hpp>

namespace dem::cli {

/// An MpiFarm under mpirun, a LocalFarm otherwise. Under mpirun without MPI in the build, an
/// InputError that says so (every rank would otherwise do the whole run in the same folder).
std::unique_ptr<parallel::TaskFarm> open_task_farm(int& argc, char**& argv);

/// The farm's processes as the subdomains of one World (World::spread_over) when it is an MpiFarm
/// of more than one rank; null otherwise (one process).
std::shared_ptr<parallel::DomainComm> open_domains(parallel::TaskFarm& farm);

/// InputError when an MPI launcher started this program on more than one rank: for the apps that
/// run in one process only (dem-cyclic-shear).
void require_one_process(const std::string& program);

/// Reports `error` (prefixed with `program`) and returns `code` for main to return. On several
/// processes an error that every rank holds (failed_together()) is reported by the leading
/// rank only; any other one is reported with the rank that has it and ends every rank.
int end_on_error(parallel::TaskFarm& farm, const std::string& program, const std::exception& error, int code,
                 std::ostream& err);

}  // namespace dem::cli
