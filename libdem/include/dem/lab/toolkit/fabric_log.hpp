// Contact fabric of a run, state by state: the rose diagrams (contact number and average contact
// force per 10-degree bin) of the study's figures after consolidation and at 20 % and 40 % shear
// strain, with their Fourier fits (docs/model.md 9), in one CSV file that a plotting script filters by
// label and plane.
//
// The file has one row per (state, plane, bin) and a header line:
//   label,shear_strain,plane,bin_lo_deg,bin_hi_deg,contact_count,contact_fraction,mean_normal_force_N,
//   a,theta_a_deg,f0_N,a_n,theta_n_deg,a_direct,theta_a_direct_deg,contacts_total,mean_force_all_N
// - label: the state's name (text); shear_strain: -, as given to record();
// - plane: "xz" (the shear plane, front view: angle atan2(n_z, n_x)) or "xy" (horizontal:
//   atan2(n_y, n_x)), angles folded into [0, 180) degrees;
// - bin columns: from dem::measure::Rose (count, count / contacts with a defined angle, mean
//   normal force of the bin in N, 0 for an empty bin);
// - a ... theta_a_direct_deg: the plane's Fourier fits, repeated on every row of the plane;
// - contacts_total, mean_force_all_N: all ball-ball contacts of the state and their mean normal
//   force (the study's Table 4), the same for both planes. A contact whose normal is
//   perpendicular to a plane has no angle there: it counts in contacts_total but in no bin.
// Text columns are why this is not an io::CsvTable. Numbers have 17 significant digits. A value
// that does not exist (the fits of a state without contacts) is an empty cell, which pandas and
// spreadsheets read as missing.
//
// Only ball-ball contacts count: contacts with the plates and rings are boundary effects, not
// the sand's fabric. Every record() rewrites the whole file atomically, so it is complete after
// each state even if the run is killed.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <dem/core/world.hpp>
#include <dem/measure/fabric.hpp>

namespace dem::lab {

class FabricLog {
 public:
  /// `csv_file` is written on the first record() (an existing file is replaced: see resume()).
  /// bin_width_deg (degrees) must divide 180 into at least 3 bins, else dem::InputError.
  explicit FabricLog(std::filesystem::path csv_file, double bin_width_deg = 10.0);

  /// Measures the ball-ball contacts of the world's last step and appends one row per plane and
  /// bin. `label` names the state: non-empty, letters, digits, '_', '-', '.' only (it goes into
  /// a CSV cell unquoted); shear_strain (-) must be finite. Otherwise dem::InputError.
  void record(const World& world, const std::string& label, double shear_strain);

  /// Continues the log of an earlier run (a resumed simulation): reads the file, keeps its first
  /// `states` states, drops the rest and rewrites it. A missing file is an empty log. Throws
  /// dem::InputError if the file has a different header or bin width, or fewer states than
  /// asked. last_roses() stays empty until the next record().
  void resume(std::size_t states);

  /// Number of states recorded (including those kept by resume()).
  std::size_t states() const { return states_; }

  /// The roses of the last record(): [0] the x-z plane, [1] the x-y plane; empty before it.
  const std::vector<measure::Rose>& last_roses() const { return last_roses_; }

  const std::filesystem::path& file() const { return csv_file_; }

 private:
  void save() const;

  std::filesystem::path csv_file_;
  double bin_width_deg_;           // degrees
  std::vector<std::string> rows_;  // data lines without the header, without '\n'
  std::size_t states_ = 0;
  std::vector<measure::Rose> last_roses_;
};

}  // namespace dem::lab
