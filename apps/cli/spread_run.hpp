// One simulation over the processes of an app's run (World::spread_over): under mpirun every rank
// runs the whole protocol on its subdomain of the same World, the leading rank writes the run's
// files in --out, and each other rank writes its identical copies into a scratch folder of its own,
// removed when the run ends. One process: --out, and nothing else changes.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <memory>
#include <ostream>

#include <dem/core/world.hpp>
#include <dem/parallel/task_farm.hpp>

namespace dem::cli {

class SpreadRun {
 public:
  SpreadRun(parallel::TaskFarm& farm, std::filesystem::path out_dir);
  ~SpreadRun();
  SpreadRun(const SpreadRun&) = delete;
  SpreadRun& operator=(const SpreadRun&) = delete;

  /// Where this process writes: --out on the leader, its scratch folder elsewhere.
  const std::filesystem::path& out_dir() const { return out_dir_; }
  /// `log` on the leader, a stream that discards everything elsewhere.
  std::ostream& log(std::ostream& log);
  /// Spreads `world` over the processes (nothing with one).
  void spread(World& world) const;
  parallel::TaskFarm& farm() const { return farm_; }

 private:
  parallel::TaskFarm& farm_;
  std::filesystem::path out_dir_;
  bool scratch_ = false;
  std::ostream discard_{nullptr};
};

}  // namespace dem::cli
