// The triaxial test's keys: one binding row per key, with its unit, range, help and resume rule
// (the stages: 0 the specimen is made, 2 the isotropic stage begins, 4 the axial one begins).
#include <dem/core/errors.hpp>
#include <dem/io/config_binding.hpp>
#include <dem/lab/protocols/triaxial.hpp>
#include <dem/lab/toolkit/resume_rules.hpp>

namespace dem::lab {

namespace {

using io::FixedAfter;
using P = RunProgress;

const io::BindingTable<CubeSpecimenConfig>& specimen_keys() {
  using S = CubeSpecimenConfig;
  static const io::BindingTable<S> table = {
      {"balls_per_side", &S::balls_per_side, "-", "balls along each edge of the lattice", 2.0, 200.0},
      {"spacing", &S::spacing, "m", "lattice spacing; at least the largest diameter", 0.0, {}, true},
      {"radius_min", &S::radius_min, "m", "smallest ball radius (uniform by number)", 0.0, {}, true},
      {"radius_max", &S::radius_max, "m", "largest ball radius", 0.0, {}, true},
      {"density", &S::density, "kg/m^3", "particle density", 0.0, {}, true},
      {"seed", &S::seed, "-", "random seed of the radii and the jitter", 0.0},
  };
  return table;
}

const io::BindingTable<IsotropicConfig>& isotropic_keys() {
  using S = IsotropicConfig;
  static const io::BindingTable<S> table = {
      {"confining_stress", &S::confining_stress, "Pa", "stress of the six walls, then of the four lateral ones", 0.0, {}, true},
      {"friction", &S::friction, "-", "ball-ball friction while the walls consolidate (0: frictionless balls, a dense specimen)", 0.0},
      {"servo_max_speed", &S::servo_max_speed, "m/s", "speed cap of the servo walls", 0.0, {}, true},
      {"equilibrium_ratio", &S::equilibrium_ratio, "-", "unbalanced force ratio that, with every wall on target, ends the stage", 0.0, {}, true},
      {"max_steps", &S::max_steps, "-", "steps after which the stage ends with a warning", 1.0},
  };
  return table;
}

const io::BindingTable<AxialConfig>& axial_keys() {
  using S = AxialConfig;
  static const io::BindingTable<S> table = {
      {"strain_rate", &S::strain_rate, "1/s", "axial strain rate (each z wall moves at half of it x the height)", 0.0, {}, true},
      {"target_strain", &S::target_strain, "-", "axial strain that ends the test", 0.0, 0.9, true, FixedAfter::never()},
      {"every_strain", &S::every_strain, "-", "axial strain between history rows", 0.0, {}, true, FixedAfter::never()},
  };
  return table;
}

// Calls visit(section, table, member, rule) for the sections that are binding tables and
// contact(section, what, member) for the contact types, in file order.
template <class Config, class Visit, class Contact>
void for_each_section(Config& c, Visit&& visit, Contact&& contact) {
  visit("specimen", specimen_keys(), c.specimen, fixed_after(P::Generating, "the specimen was made with it"));
  contact("ball_ball", "ball-ball", c.ball_ball);
  contact("ball_wall", "ball-wall", c.ball_wall);
  visit("engine", engine_keys(), c.engine, std::nullopt);
  visit("isotropic", isotropic_keys(), c.isotropic, fixed_after(P::Consolidating, "the isotropic stage ran with it"));
  visit("axial", axial_keys(), c.axial, fixed_after(P::Shearing, "the axial stage so far ran with it"));
  visit("output", run_output_keys(), c.output, FixedAfter::never());
}

}  // namespace

io::Schema triaxial_schema() {
  io::Schema schema;
  const TriaxialConfig defaults;
  for_each_section(
      defaults, [&](const std::string& section, const auto& table, const auto& value, const auto& rule) { io::add_keys(schema, section, table, value, rule); },
      [&](const std::string& section, const std::string& what, const ContactTypeConfig& value) {
        // The ball-ball friction of the isotropic stage is its own key; the law's from the axial stage on.
        add_contact_keys(schema, section, what, value,
                         {fixed_after(P::Generating, "the contacts so far had it"), fixed_after(P::Generating, "the contacts so far had it"),
                          fixed_after(P::Shearing, "the axial stage so far ran with it")});
      });
  return schema;
}

TriaxialConfig triaxial_config(const io::Config& config) {
  TriaxialConfig c;
  for_each_section(
      c, [&](const std::string& section, const auto& table, auto& value, const auto&) { io::read_keys(config, section, table, value); },
      [&](const std::string& section, const std::string&, ContactTypeConfig& value) { value = read_contact_keys(config, section); });
  return c;  // the checks across keys: TriaxialTest's constructor
}

}  // namespace dem::lab
