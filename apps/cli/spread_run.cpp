#include "spread_run.hpp"

#include <unistd.h>

#include <string>
#include <system_error>

#include "task_farm.hpp"

namespace dem::cli {

SpreadRun::SpreadRun(parallel::TaskFarm& farm, std::filesystem::path out_dir) : farm_(farm), out_dir_(std::move(out_dir)) {
  if (farm_.leads()) return;
  // Each rank of each run its own: ranks may share a machine, runs may share a scratch space.
  out_dir_ = std::filesystem::temp_directory_path() /
             ("libdem-" + std::to_string(::getpid()) + "-rank-" + std::to_string(farm_.process()));
  scratch_ = true;
}

SpreadRun::~SpreadRun() {
  if (!scratch_) return;
  std::error_code ignored;  // a scratch folder left behind is not worth an error at exit
  std::filesystem::remove_all(out_dir_, ignored);
}

std::ostream& SpreadRun::log(std::ostream& log) { return farm_.leads() ? log : discard_; }

void SpreadRun::spread(World& world) const {
  if (auto domains = open_domains(farm_)) world.spread_over(std::move(domains));
}

}  // namespace dem::cli
