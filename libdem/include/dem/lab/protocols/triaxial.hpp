// A drained triaxial test on a cube of balls between six servo-controlled walls, as a protocol
// over the lab toolkit (examples/triaxial_cube.cpp, the same test written by hand, made resumable
// and configurable): a polydisperse specimen on a jittered lattice, compressed isotropically to the
// confining stress by six servo walls with frictionless balls (a dense specimen), then compressed
// axially at a constant strain rate by the two z walls while the four lateral walls hold the
// confining stress, with the sand's friction and rolling resistance on.
//
// Stresses are compression positive: sigma_a the mean of the z walls', sigma_r the mean of the
// four lateral walls', each over the wall's current loaded face; p = (sigma_a + 2 sigma_r) / 3,
// q = sigma_a - sigma_r. Strains are compression positive: axial 1 - H / H_0, volumetric
// 1 - V / V_0 from the walls' positions, H_0 and V_0 at the end of the isotropic stage.
//
// Outputs in the run's folder: history.csv (a row every output.every_strain of axial strain),
// summary.json (peak q/p, the final state, the configuration), restart files in every stage
// (restart.restart, consolidated.restart, final.restart), from which a run resumes exactly.
// Keys: triaxial_schema(); `dem-triaxial --help` lists them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>

#include <dem/control/servo_wall.hpp>
#include <dem/io/config.hpp>
#include <dem/lab/toolkit/contact_config.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

/// [specimen]: balls on a jittered cubic lattice, without initial overlaps.
struct CubeSpecimenConfig {
  int balls_per_side = 10;
  double spacing = 1.02e-3;      // m, of the lattice
  double radius_min = 0.35e-3;   // m
  double radius_max = 0.5e-3;    // m
  double density = 2650.0;       // kg/m^3
  std::uint64_t seed = 2024;
  bool operator==(const CubeSpecimenConfig&) const = default;
};

/// [isotropic]: the six servo walls bring the specimen to the confining stress.
struct IsotropicConfig {
  double confining_stress = 100e3;  // Pa
  double friction = 0.0;            // -, ball-ball friction meanwhile (0: a dense specimen)
  double servo_max_speed = 1.0;     // m/s
  double equilibrium_ratio = 1e-2;  // -, unbalanced force ratio that, with every wall on target, ends the stage
  long max_steps = 400000;
  bool operator==(const IsotropicConfig&) const = default;
};

/// [axial]: the drained compression.
struct AxialConfig {
  double strain_rate = 8.0;     // 1/s, of the specimen's height
  double target_strain = 0.12;  // -, axial
  double every_strain = 0.002;  // -, between history rows
  bool operator==(const AxialConfig&) const = default;
};

struct TriaxialConfig {
  CubeSpecimenConfig specimen;
  ContactTypeConfig ball_ball = ContactTypeConfig::rolling_linear(5e7, 1.5, 0.5, 0.1);
  ContactTypeConfig ball_wall = ContactTypeConfig::rolling_linear(5e7, 1.0, 0.0, 0.0);
  EngineConfig engine;
  IsotropicConfig isotropic;
  AxialConfig axial;
  OutputConfig output;  // restart_every_steps and progress_seconds are read
  bool operator==(const TriaxialConfig&) const = default;
};

/// Every key, with the defaults of TriaxialConfig{} and each key's resume rule.
io::Schema triaxial_schema();
/// The typed configuration from validated values.
TriaxialConfig triaxial_config(const io::Config& config);

class TriaxialTest {
 public:
  TriaxialTest(TriaxialConfig config, std::filesystem::path out_dir, std::ostream& log);
  void record_configuration(const io::Config& resolved) { run_.record_configuration(resolved); }
  /// Goes on from a restart file of this test, in any stage (the recorded keys checked).
  void load_restart(const std::filesystem::path& file);
  void open_outputs(const OutputOptions& options = {}) { run_.claim(options); }
  /// Whatever remains of the specimen, the isotropic and the axial stage.
  void run();
  void write_summary(const std::string& resolved_config_json) const;

  static std::vector<std::string> run_files();
  World& world() { return run_.world(); }
  const HistoryLog& history() const { return history_; }

 private:
  enum class Stage : int { Empty = 0, Isotropic = 1, Consolidated = 2, Axial = 3, Done = 4 };
  double gap(int axis) const;  // m, between the walls of an axis
  void control(World& world);
  void add_columns();
  void set_laws(bool sand, bool keep_contacts);

  TriaxialConfig config_;
  Run run_;
  HistoryLog history_;
  std::array<std::unique_ptr<ServoWall>, 6> servos_;
  Stage stage_ = Stage::Empty;
  std::int64_t stage_start_step_ = 0;
  double height0_ = 0.0, volume0_ = 0.0;  // m, m^3: at the end of the isotropic stage
  double next_row_strain_ = 0.0;
  double peak_ratio_ = 0.0, peak_strain_ = 0.0;  // q/p, axial strain
};

}  // namespace dem::lab
