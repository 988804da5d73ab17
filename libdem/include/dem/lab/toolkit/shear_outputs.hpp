// The outputs of a simple shear in the NGI cell, as a part: history.csv (a row every
// output.every_strain of shear strain: the plates, the rings, the measurement sphere, the
// uniformity of the shear, docs/model.md 8 and 8.1), fabric.csv (roses at output.fabric_strains)
// and snapshots/ (ParaView, at output.snapshot_strains; with cementation, the broken bonds too). It keeps its counters and the profile's
// reference positions in the run's restart files, and continues the files of a loaded run.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/ngi_specimen.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/uniformity_probe.hpp>

namespace dem::lab {

class BrokenBondLog;
class FabricLog;
class SnapshotWriter;

class ShearOutputs {
 public:
  /// The files in `run`'s folder (written from the first record()); `direction` gives the shear
  /// direction of a row (a unit vector in x-y). `run` and `specimen` must outlive it.
  ShearOutputs(Run& run, const NgiSpecimen& specimen, std::function<Vec3()> direction);
  ~ShearOutputs();

  /// The files a run of these outputs writes, and those a resumed run continues.
  static std::vector<std::string> files() { return {"history.csv", "fabric.csv", "snapshots"}; }

  /// At shear strain `strain`: the history row when due (or `force`d), then the roses and
  /// snapshots due. The row stops the run (InstabilityError) if a ball has left the specimen.
  void record(double strain, bool force);
  /// The next row falls at shear strain `strain` (0 at a consolidation's end: its row is the
  /// shear's first; output.every_strain when the shear starts).
  void next_row_at(double strain) { next_row_strain_ = strain; }

  const HistoryLog& history() const { return history_; }

 private:
  void add_columns();

  Run& run_;
  const NgiSpecimen& specimen_;
  std::function<Vec3()> direction_;
  HistoryLog history_;
  ShearState row_;  // measured for the row being written
  std::unique_ptr<UniformityProbe> uniformity_;
  std::unique_ptr<FabricLog> fabric_;
  std::unique_ptr<SnapshotWriter> snapshots_;
  std::unique_ptr<BrokenBondLog> broken_bonds_;  // a cemented run's: snapshots/broken_bonds_<label>.vtp
  double next_row_strain_ = 0.0;
  std::size_t next_fabric_ = 0, next_snapshot_ = 0;
  double shear_strain_ = 0.0;  // of the row being written, for the escape message
};

}  // namespace dem::lab
