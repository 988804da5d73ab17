// Every parameter of the cyclic stage of a simple-shear test (file section [cyclic], keys
// cyclic.<field>), declared once: the struct's default member values are the schema's defaults,
// and one binding table (cyclic_shear_config.cpp) gives each field its key (= the field's name),
// unit, range and help. docs/cyclic-shear.md describes the test.
#pragma once

#include <string>
#include <vector>

#include <dem/io/config.hpp>
#include <dem/lab/toolkit/cyclic_path.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

/// What the path prescribes: the top plate's shear stress (a servo on its horizontal force) or
/// the shear strain (the bottom plate's displacement).
enum class CyclicControl { Stress, Strain };
/// constant-volume: the height is held (the equivalent of undrained); drained: the vertical
/// stress is held by the servo.
enum class CyclicDrainage { ConstantVolume, Drained };

struct CyclicShearConfig {
  CyclicControl control = CyclicControl::Stress;
  CyclicShape path = CyclicShape::Sine;
  CyclicDrainage drainage = CyclicDrainage::ConstantVolume;
  double direction_deg = 0.0;       // deg, of the sine, the ellipse's major axis, the figure-8's long axis
  double csr = 0.2;                 // -, cyclic stress ratio tau_amplitude / sigma'_v0 (stress control)
  double strain_amplitude = 0.005;  // -, shear strain amplitude (strain control)
  double minor_ratio = 0.5;         // -, ellipse minor / major axis; figure-8 transverse amplitude / amplitude
  std::string series_file;          // CSV of the series path (path = series)
  double period = 0.0;              // s, one cycle; 0: 4 x 0.01 / the shear rate of shear.inertial_number
  double static_csr = 0.0;          // -, static shear stress / sigma'_v0 applied before the cycles
  double static_direction_deg = 0.0;  // deg
  long max_cycles = 20;             // cycles that end the test
  double ru_limit = 0.9;            // -, r_u that ends the test; 0: none
  double da_strain_limit = 0.05;    // -, double-amplitude shear strain that ends the test; 0: none
  long rows_per_cycle = 40;         // history rows per cycle
  double post_strain = 0.0;         // -, monotonic shear strain after the cycles; 0: none
  double post_direction_deg = 0.0;  // deg
  double servo_relaxation = 1.0;    // -, fraction of the shear stress error the plate removes per step
  double servo_max_speed = 0.0;     // m/s, cap of the stress-controlled plate; 0: 10 x the shear rate x H_c
  std::vector<double> snapshot_cycles{};  // cycles at which snapshots are written
  std::vector<double> fabric_cycles{};    // cycles at which the fabric is recorded

  bool operator==(const CyclicShearConfig&) const = default;
};

/// The [cyclic] keys, with the defaults of CyclicShearConfig{}.
void add_cyclic_shear_keys(io::Schema& schema);
/// The keys of a cyclic test: simple_shear_schema() (the specimen) and the [cyclic] keys.
io::Schema cyclic_shear_schema();
/// The typed configuration from validated values of a schema holding the [cyclic] keys.
/// InputError naming the key for a series path without a file.
CyclicShearConfig cyclic_shear_config(const io::Config& config);

}  // namespace dem::lab
