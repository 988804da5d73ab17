#include <dem/lab/protocols/cyclic_shear_config.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>

#include <string>

#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>

namespace dem::lab {

namespace {

using C = CyclicShearConfig;
using io::enum_choice;

const io::BindingTable<C>& bindings() {
  static const io::BindingTable<C> table = {
      {"control", enum_choice({"stress", "strain"}, &C::control), "-",
       "stress: the path is the top plate's shear stress (servo on its horizontal force); strain: the shear strain (bottom plate displacement)"},
      {"path", enum_choice({"sine", "circle", "ellipse", "figure8", "series"}, &C::path), "-",
       "shape in the horizontal plane: sine (one-directional), circle, ellipse, figure8, series (cyclic.series_file)"},
      {"drainage", enum_choice({"constant-volume", "drained"}, &C::drainage), "-",
       "constant-volume: height held, r_u = (sigma_v0 - sigma_v) / sigma_v0; drained: vertical stress held by the servo"},
      {"direction_deg", &C::direction_deg, "deg", "direction of the sine, the ellipse's major axis, the figure-8's long axis, from +x towards +y", -360.0, 360.0},
      {"csr", &C::csr, "-", "cyclic stress ratio: shear stress amplitude / sigma'_v0 (control = stress)", 0.0, 2.0, true},
      {"strain_amplitude", &C::strain_amplitude, "-", "shear strain amplitude (control = strain)", 0.0, 0.5, true},
      {"minor_ratio", &C::minor_ratio, "-", "ellipse minor / major axis; figure-8 transverse amplitude / amplitude", 0.0, 10.0},
      {"series_file", &C::series_file, "-", "CSV of the series path: columns cycle (or time, s), x, y in CSR (stress) or strain"},
      {"period", &C::period, "s", "duration of one cycle; 0: 4 x 0.01 / the shear rate of shear.inertial_number (a quarter cycle at the monotonic rate per 1 % strain)", 0.0, 1e4},
      {"static_csr", &C::static_csr, "-", "static shear stress / sigma'_v0 applied (over a quarter period, then held) before the cycles; 0: none", 0.0, 2.0},
      {"static_direction_deg", &C::static_direction_deg, "deg", "direction of the static shear stress", -360.0, 360.0},
      {"max_cycles", &C::max_cycles, "-", "cycles that end the test", 1.0, 100000.0, false, io::FixedAfter::never()},
      {"ru_limit", &C::ru_limit, "-", "excess pore pressure ratio r_u that ends the test (its cycle is N_L by r_u); 0: not a criterion", 0.0, 1.0, false, io::FixedAfter::never()},
      {"da_strain_limit", &C::da_strain_limit, "-", "double-amplitude shear strain over the last cycle that ends the test (N_L by strain); 0: not a criterion", 0.0, 2.0, false, io::FixedAfter::never()},
      {"rows_per_cycle", &C::rows_per_cycle, "-", "history rows per cycle (loops are drawn from them)", 4.0, 10000.0},
      {"post_strain", &C::post_strain, "-", "monotonic shear strain after the cycles, strain-controlled at the shear rate; 0: none", 0.0, 2.0},
      {"post_direction_deg", &C::post_direction_deg, "deg", "direction of the post-cyclic shear", -360.0, 360.0},
      {"servo_relaxation", &C::servo_relaxation, "-", "stress control: fraction of the shear stress error the top plate removes per step (gain alpha A / (sum k_s dt))", 0.0, 1.0, true},
      {"servo_max_speed", &C::servo_max_speed, "m/s", "stress control: speed cap of the top plate; 0: 10 x the shear rate x H_c", 0.0, 100.0},
      {"snapshot_cycles", &C::snapshot_cycles, "-", "cycles N at which snapshots are written (cyclic_snapshots/)", 0.0, {}, false, io::FixedAfter::never()},
      {"fabric_cycles", &C::fabric_cycles, "-", "cycles N at which the fabric is recorded (cyclic_fabric.csv)", 0.0, {}, false, io::FixedAfter::never()},
  };
  return table;
}

}  // namespace

// A cyclic stage resumed from a restart file goes on with the keys it began with; its stop
// criteria and outputs may change.
void add_cyclic_shear_keys(io::Schema& schema) {
  io::add_keys(schema, "cyclic", bindings(), C{}, fixed_after(RunProgress::Shearing, "the cyclic stage so far ran with it"));
}

io::Schema cyclic_shear_schema() {
  io::Schema schema = simple_shear_schema();
  add_cyclic_shear_keys(schema);
  return schema;
}

CyclicShearConfig cyclic_shear_config(const io::Config& config) {
  C c;
  io::read_keys(config, "cyclic", bindings(), c);
  require(c.path != CyclicShape::Series || !c.series_file.empty(), "cyclic.series_file", "(empty)",
          "a CSV file when cyclic.path = series");
  require(c.path == CyclicShape::Series || c.series_file.empty(), "cyclic.series_file", c.series_file,
          "empty unless cyclic.path = series (the file would be ignored)");
  require(c.ru_limit > 0 || c.da_strain_limit > 0 || c.max_cycles > 0, "cyclic stop criteria", "none", "at least one");
  return c;
}

}  // namespace dem::lab
