// Element tests in a periodic cell (docs/periodic.md): a specimen without walls, made by
// lab/toolkit/periodic_specimen.hpp (a seeded gas of the preset's balls compressed isotropically
// by the cell servo to element.confining_stress), then loaded by the cell's velocity gradient
// (control/cell_servo.hpp) along one of these paths (element.test):
//
//   isotropic             the compression to the confining stress is the test (rows meanwhile)
//   triaxial-drained      zz shortened at the strain rate; xx and yy hold the confining stress
//   triaxial-undrained    zz shortened at the strain rate; xx at half of it outward and yy by
//                         hold_volume: constant volume, the lateral strains equal
//   simple-shear          L_xz at the shear rate; zz holds the confining stress, xx yy fixed
//   simple-shear-undrained  L_xz at the shear rate; every normal rate zero: constant volume
//   cyclic-simple-shear   every normal rate zero (constant volume); the shear strains F_xz, F_yz
//                         (strain control) or the shear stresses (stress control) follow one of
//                         the cyclic app's paths (lab/toolkit/cyclic_path.hpp) for element.cycles
//
// Stresses are the cell stress (measure/cell_stress.hpp), compression positive: p the mean of the
// normal stresses, q = sigma_zz - (sigma_xx + sigma_yy) / 2 (the triaxial app's), the shear stress
// sigma_xz. Strains from the cell at the start of the loading (of the compression for the
// isotropic test), compression positive: axial 1 - h_zz / h0_zz, volumetric 1 - V / V0, shear
// F_xz of F = h h0^-1.
//
// Outputs in the run's folder: history.csv (a row every element.every_strain of the test's strain:
// volumetric, axial or shear; element.rows_per_cycle a cycle in the cyclic test), summary.json (peak q/p, the end state), restart files in every
// stage (restart.restart, consolidated.restart, final.restart), from which a run resumes exactly.
// With cementation.after (docs/cementation.md), bonds are installed once the specimen is placed or
// once it is compressed (after consolidated.restart is written), and history.csv counts them;
// broken_bonds.vtp, written at the end, holds the broken ones (lab/toolkit/broken_bonds.hpp), each
// with the test's strain it broke at (test_strain_broken; cycles_broken in the cyclic test).
// Keys: element_test_schema(); `dem-element-test --help` lists them.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/lab/protocols/cyclic_shear_config.hpp>
#include <dem/lab/toolkit/broken_bonds.hpp>
#include <dem/lab/toolkit/cementation.hpp>
#include <dem/lab/toolkit/contact_config.hpp>
#include <dem/lab/toolkit/cyclic_path.hpp>
#include <dem/lab/toolkit/grading.hpp>
#include <dem/lab/toolkit/history_log.hpp>
#include <dem/lab/toolkit/periodic_profile.hpp>
#include <dem/lab/toolkit/periodic_specimen.hpp>
#include <dem/lab/toolkit/run.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

enum class ElementTestKind {
  Isotropic = 0, TriaxialDrained = 1, TriaxialUndrained = 2, SimpleShear = 3, SimpleShearUndrained = 4, CyclicSimpleShear = 5
};
/// The key's word for `kind` ("triaxial-drained").
std::string to_string(ElementTestKind kind);
/// Triaxial tests: zz shortened (compression) or lengthened (extension).
enum class TriaxialDirection { Compression = 0, Extension = 1 };
/// triaxial-drained: what the lateral stresses hold.
enum class DrainedPath {
  ConstantSigma3 = 0,  // sigma_xx = sigma_yy = confining_stress
  ConstantP = 1        // sigma_xx = sigma_yy = (3 confining_stress - sigma_zz) / 2: p = confining_stress
};

/// [element]: the specimen in the cell and the loading path.
struct ElementConfig {
  ElementTestKind test = ElementTestKind::TriaxialDrained;
  double confining_stress = 100e3;  // Pa, of the isotropic compression, then held where the path holds a stress
  double target_strain = 0.10;      // -, axial (triaxial), shear (simple shear) or volumetric (isotropic, none: until the stress)
  double strain_rate = 0.0;         // 1/s, axial or shear; 0: from inertial_number
  double inertial_number = 1e-3;    // -, sets the strain rate unless strain_rate > 0
  double every_strain = 0.005;      // -, of the test's strain between history rows
  long balls = 4000;                // -, in the cell
  std::uint64_t seed = 1;           // -, of the diameters and positions
  double density = 2650.0;          // kg/m^3
  double initial_solid_fraction = 0.3;  // -, of the gas the balls are placed in
  double compaction_friction = 0.0;     // -, ball-ball friction while compressing (0: dense)
  TriaxialDirection direction = TriaxialDirection::Compression;  // triaxial tests
  DrainedPath drained_path = DrainedPath::ConstantSigma3;         // triaxial-drained
  double tolerance = 0.005;             // -, relative stress error that ends the compression
  double equilibrium_ratio = 1e-2;      // -, unbalanced force ratio that ends it
  double servo_max_rate = 10.0;         // 1/s, cap of the servo's rates
  long max_compaction_steps = 400000;
  // The cyclic simple shear (test = cyclic-simple-shear), keys named as the cyclic app's.
  CyclicControl cyclic_control = CyclicControl::Strain;  // the shear strains or the shear stresses follow the path
  CyclicShape cyclic_path = CyclicShape::Sine;           // sine, circle, ellipse, figure8 or series
  std::string cyclic_series_file;                        // series: CSV of cycle (or time, s), x, y
  CyclicDrainage cyclic_drainage = CyclicDrainage::ConstantVolume;  // or drained: sigma_zz held
  double strain_amplitude = 0.001;   // -, of F_xz (and F_yz), strain control
  double csr = 0.1;                  // -, shear stress amplitude / confining_stress, stress control
  double cyclic_direction_deg = 0.0; // deg, of the sine, the ellipse's major axis, the figure-8's long axis
  double cyclic_minor_ratio = 0.5;   // -, ellipse minor / major axis; figure-8 transverse amplitude / amplitude
  double cyclic_period = 0.0;        // s, one cycle; 0: 4 x 0.01 / the strain rate (the cyclic app's rule)
  double cycles = 2.0;               // -, cycles that end the test
  long rows_per_cycle = 40;          // -, history rows per cycle
  bool operator==(const ElementConfig&) const = default;
};

struct ElementTestConfig {
  Grading grading = SimpleShearConfig{}.grading;
  ContactTypeConfig ball_ball = SimpleShearConfig{}.ball_ball;
  EngineConfig engine;
  ElementConfig element;
  CementationConfig cementation;  // bonds between close balls (docs/cementation.md)
  OutputConfig output;  // restart_every_steps and progress_seconds are read
  bool operator==(const ElementTestConfig&) const = default;
};

/// Every key, with the defaults of ElementTestConfig{} (the 4D preset's material) and each key's
/// resume rule.
io::Schema element_test_schema();
/// The typed configuration from validated values; InputError naming the key for checks across keys.
ElementTestConfig element_test_config(const io::Config& config);

class ElementTest {
 public:
  ElementTest(ElementTestConfig config, std::filesystem::path out_dir, std::ostream& log);
  void record_configuration(const io::Config& resolved) { run_.record_configuration(resolved); }
  /// Goes on from a restart file of this test, in any stage (the recorded keys checked).
  void load_restart(const std::filesystem::path& file);
  void open_outputs(const OutputOptions& options = {}) { run_.claim(options); }
  /// Whatever remains of the specimen and the loading.
  void run();
  void write_summary(const std::string& resolved_config_json) const;

  static std::vector<std::string> run_files();
  World& world() { return run_.world(); }
  const HistoryLog& history() const { return history_; }
  /// 1/s, the loading's axial or shear rate (element.strain_rate, or from the inertial number).
  double strain_rate() const;
  /// s, one cycle of the cyclic test (element.cyclic_period, or 4 x 0.01 / strain_rate()).
  double cyclic_period() const;

 private:
  enum class Stage : int { Specimen = 0, Loading = 1, Done = 2 };
  void start_loading();
  void set_path();
  double test_strain() const;  // -, the one every_strain and target_strain count (cycles when cyclic)
  double axial_sign() const;   // +1: zz shortened (triaxial compression), -1: lengthened (extension)
  double row_spacing() const;  // of test_strain() between rows
  double test_end() const;     // test_strain() that ends the loading
  /// The cyclic path's target at time t (s): F_xz, F_yz (strain control) or tau_xz, tau_yz (Pa).
  Vec3 cyclic_target(double time) const;
  void record_row();
  /// Bonds the close pairs now (cementation.*, strengths keyed by element.seed).
  void cement_now();
  void add_columns();
  Mat3 reference() const;

  ElementTestConfig config_;
  Run run_;
  HistoryLog history_;
  PeriodicSpecimen specimen_;
  Stage stage_ = Stage::Specimen;
  std::array<double, 9> reference_{};  // m, the cell the strains count from (row-major)
  double next_row_strain_ = 0.0;
  double loading_start_time_ = 0.0;  // s, the World's time when the loading began (the cycles count from it)
  double peak_ratio_ = 0.0, peak_strain_ = 0.0;  // q/p (|tau|/sigma_zz in simple shear), the test's strain
  CyclicPath cyclic_path_{CyclicShape::Sine, 0.0, 0.0};  // element.cyclic_path, read once (a series from its file)
  PeriodicInterval profile_start_;  // the simple shears' profile: where the balls were at the last row
  double profile_r2_ = 0.0;         // its R^2 over the interval that ended at the row being recorded
  PeriodicInterval span_start_;     // ... and at the first row at 20 % shear strain (the NGI cell's span)
  double span_from_strain_ = 0.0;   // -, the shear strain of that row
  std::unique_ptr<BrokenBondLog> broken_bonds_;  // a cemented run's: the test's strain each bond broke at
};

}  // namespace dem::lab
