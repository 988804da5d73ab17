// The element test's keys: one binding row per key, with its unit, range, help and resume rule
// (the stages: the specimen is placed, compressed, then loaded).
#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>
#include <dem/lab/protocols/element_test.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>

namespace dem::lab {

namespace {

using io::FixedAfter;
using P = RunProgress;

const io::BindingTable<Grading>& element_grading_keys() {
  using S = Grading;
  static const io::BindingTable<S> table = {
      {"d_min", &S::d_min, "m", "smallest diameter before scaling (uniform by number)", 0.0, 1.0, true},
      {"d_max", &S::d_max, "m", "largest diameter before scaling", 0.0, 1.0, true},
      {"scale", &S::scale, "-", "particle size multiplier (1D, 2D, 4D = 1, 2, 4)", 0.0, 1000.0, true},
  };
  return table;
}

const io::BindingTable<ElementConfig>& element_keys() {
  using S = ElementConfig;
  const FixedAfter made = fixed_after(P::Generating, "the specimen was made with it");
  const FixedAfter compressed = fixed_after(P::Consolidating, "the isotropic compression ran with it");
  const FixedAfter loaded = fixed_after(P::Shearing, "the loading so far ran with it");
  static const io::BindingTable<S> table = {
      {"test", io::enum_choice({"isotropic", "triaxial-drained", "triaxial-undrained", "simple-shear", "simple-shear-undrained", "cyclic-simple-shear"}, &S::test), "-",
       "the loading path: isotropic (the compression to confining_stress is the test), triaxial-drained (zz shortened, xx yy hold "
       "confining_stress), triaxial-undrained (zz shortened at constant volume), simple-shear (L_xz, zz holds confining_stress), "
       "simple-shear-undrained (L_xz at constant volume), cyclic-simple-shear (constant volume, the shear strains or stresses along "
       "cyclic_path); a compressed specimen (consolidated.restart) may be loaded along another",
       {}, {}, false, loaded},
      {"confining_stress", &S::confining_stress, "Pa", "isotropic stress the specimen is compressed to, then held where the path holds a stress", 0.0, 1e9, true, compressed},
      {"target_strain", &S::target_strain, "-", "axial (triaxial) or shear (simple shear, at most 0.5) strain that ends the test", 0.0, 0.5, true, FixedAfter::never()},
      {"strain_rate", &S::strain_rate, "1/s", "axial or shear strain rate; 0: from inertial_number", 0.0, 1e4, false, loaded},
      {"inertial_number", &S::inertial_number, "-", "I = rate d_mean sqrt(density / confining_stress), sets the rate unless strain_rate > 0", 0.0, 0.1, true, loaded},
      {"every_strain", &S::every_strain, "-", "strain of the test (volumetric when isotropic) between history rows", 0.0, 1.0, true, FixedAfter::never()},
      {"balls", &S::balls, "-", "balls in the cell", 2.0, 1e7, false, made},
      {"seed", &S::seed, "-", "random seed of the diameters and positions", 0.0, {}, false, made},
      {"density", &S::density, "kg/m^3", "particle density", 1.0, 1e5, false, made},
      {"initial_solid_fraction", &S::initial_solid_fraction, "-", "solid fraction of the gas the balls are placed in", 0.0, 0.5, true, made},
      {"direction", io::enum_choice({"compression", "extension"}, &S::direction), "-",
       "triaxial tests: compression (zz shortened; axial strain and q positive) or extension (zz lengthened; both negative, "
       "target_strain is the magnitude)", {}, {}, false, loaded},
      {"drained_path", io::enum_choice({"constant-sigma3", "constant-p"}, &S::drained_path), "-",
       "triaxial-drained: xx and yy hold confining_stress (constant-sigma3), or hold the mean stress p at confining_stress "
       "(constant-p: sigma_xx = sigma_yy = (3 confining_stress - sigma_zz) / 2)", {}, {}, false, loaded},
      {"compaction_friction", &S::compaction_friction, "-", "ball-ball friction while compressing: 0 a dense specimen, ball_ball's a loose one", 0.0, 10.0, false, compressed},
      {"tolerance", &S::tolerance, "-", "relative error of every stress component that ends the compression", 0.0, 0.5, true, compressed},
      {"equilibrium_ratio", &S::equilibrium_ratio, "-", "unbalanced force ratio that ends the compression", 0.0, 1.0, true, compressed},
      {"servo_max_rate", &S::servo_max_rate, "1/s", "cap on the cell servo's rates", 0.0, 1e4, true, compressed},
      {"max_compaction_steps", &S::max_compaction_steps, "-", "steps after which the compression ends with a warning", 1.0, 1e12, false, compressed},
      {"cyclic_control", io::enum_choice({"stress", "strain"}, &S::cyclic_control), "-",
       "cyclic-simple-shear: strain (F_xz, F_yz follow the path) or stress (the shear stresses follow it, held by the servo)", {}, {}, false, loaded},
      {"cyclic_path", io::enum_choice({"sine", "circle", "ellipse", "figure8", "series"}, &S::cyclic_path), "-",
       "cyclic-simple-shear: the cyclic app's path shape (docs/cyclic-shear.md), in the xz-yz shear plane; series: "
       "cyclic_series_file", {}, {}, false, loaded},
      {"cyclic_series_file", &S::cyclic_series_file, "-",
       "cyclic-simple-shear, path series: CSV with columns cycle (or time, s), x, y: the shear strains F_xz, F_yz (strain "
       "control) or the shear stresses / confining_stress (stress control); the test ends at its last row or at cycles",
       {}, {}, false, loaded},
      {"cyclic_drainage", io::enum_choice({"constant-volume", "drained"}, &S::cyclic_drainage), "-",
       "cyclic-simple-shear: constant-volume (every normal rate zero) or drained (sigma_zz holds confining_stress)",
       {}, {}, false, loaded},
      {"strain_amplitude", &S::strain_amplitude, "-", "cyclic-simple-shear, strain control: amplitude of the shear strain", 0.0, 0.5, true, loaded},
      {"csr", &S::csr, "-", "cyclic-simple-shear, stress control: shear stress amplitude / confining_stress", 0.0, 2.0, true, loaded},
      {"cyclic_direction_deg", &S::cyclic_direction_deg, "deg", "direction of the sine, the ellipse's major axis, the figure-8's long axis, from x towards y", -360.0, 360.0, false, loaded},
      {"cyclic_minor_ratio", &S::cyclic_minor_ratio, "-", "ellipse minor / major axis; figure-8 transverse amplitude / amplitude", 0.0, 10.0, false, loaded},
      {"cyclic_period", &S::cyclic_period, "s", "duration of one cycle; 0: 4 x 0.01 / the strain rate (the cyclic app's rule)", 0.0, 1e4, false, loaded},
      {"cycles", &S::cycles, "-", "cycles that end cyclic-simple-shear", 0.0, 1e5, true, FixedAfter::never()},
      {"rows_per_cycle", &S::rows_per_cycle, "-", "history rows per cycle of cyclic-simple-shear", 4.0, 1e4, false, loaded},
  };
  return table;
}

// Calls visit(section, table, member, rule) for the sections that are binding tables and
// contact(section, what, member) for the contact type, in file order.
template <class Config, class Visit, class Contact>
void for_each_section(Config& c, Visit&& visit, Contact&& contact) {
  visit("grading", element_grading_keys(), c.grading, fixed_after(P::Generating, "the specimen was made with it"));
  contact("ball_ball", "ball-ball", c.ball_ball);
  visit("engine", engine_keys(), c.engine, std::nullopt);
  visit("element", element_keys(), c.element, std::nullopt);
  visit("cementation", cementation_keys(), c.cementation, fixed_after(P::Shearing, "the bonds were installed with it"));
  visit("output", run_output_keys(), c.output, FixedAfter::never());
}

}  // namespace

io::Schema element_test_schema() {
  io::Schema schema;
  const ElementTestConfig defaults;
  for_each_section(
      defaults, [&](const std::string& section, const auto& table, const auto& value, const auto& rule) { io::add_keys(schema, section, table, value, rule); },
      [&](const std::string& section, const std::string& what, const ContactTypeConfig& value) {
        // The friction while compressing is element.compaction_friction; the law's from the loading on.
        add_contact_keys(schema, section, what, value,
                         {fixed_after(P::Generating, "the contacts so far had it"), fixed_after(P::Generating, "the contacts so far had it"),
                          fixed_after(P::Shearing, "the loading so far ran with it")});
      });
  return schema;
}

ElementTestConfig element_test_config(const io::Config& config) {
  ElementTestConfig c;
  for_each_section(
      c, [&](const std::string& section, const auto& table, auto& value, const auto&) { io::read_keys(config, section, table, value); },
      [&](const std::string& section, const std::string&, ContactTypeConfig& value) { value = read_contact_keys(config, section); });
  require(c.grading.d_min <= c.grading.d_max, "grading.d_min", c.grading.d_min, "<= grading.d_max = " + io::real_text(c.grading.d_max));
  c.grading.validate("grading");
  const bool series = c.element.cyclic_path == CyclicShape::Series;
  require(!series || !c.element.cyclic_series_file.empty(), "element.cyclic_series_file", "(empty)",
          "a CSV file when element.cyclic_path = series");
  require(series || c.element.cyclic_series_file.empty(), "element.cyclic_series_file", c.element.cyclic_series_file,
          "empty unless element.cyclic_path = series (the file would be ignored)");
  if (series) (void)CyclicPath::from_csv(c.element.cyclic_series_file, 1.0);  // refused at the door, naming the file
  return c;
}

}  // namespace dem::lab
