#include <dem/lab/cyclic_shear_config.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>
#include <variant>

#include <dem/core/errors.hpp>

namespace dem::lab {

namespace {

using C = CyclicShearConfig;

// A text key for an enum field: its choices and the conversions.
struct Choice {
  std::vector<std::string> choices;
  std::function<std::string(const C&)> get;
  std::function<void(C&, const std::string&)> set;
};

using Member = std::variant<double C::*, long C::*, std::string C::*, std::vector<double> C::*, Choice>;

struct Binding {
  std::string name;  // the key is "cyclic." + name, the field's name
  Member member;
  std::string unit;
  std::string help;
  std::optional<double> min{}, max{};
  bool min_exclusive = false;
};

template <class E>
Choice choice(std::vector<std::string> names, E C::*field) {
  return {names, [names, field](const C& c) { return names[static_cast<std::size_t>(c.*field)]; },
          [names, field](C& c, const std::string& v) {
            for (std::size_t k = 0; k < names.size(); ++k)
              if (names[k] == v) c.*field = static_cast<E>(k);
          }};
}

const std::vector<Binding>& bindings() {
  static const std::vector<Binding> table = {
      {"control", choice({"stress", "strain"}, &C::control), "-",
       "stress: the path is the top plate's shear stress (servo on its horizontal force); strain: the shear strain (bottom plate displacement)"},
      {"path", choice({"sine", "circle", "ellipse", "figure8", "series"}, &C::path), "-",
       "shape in the horizontal plane: sine (one-directional), circle, ellipse, figure8, series (cyclic.series_file)"},
      {"drainage", choice({"constant-volume", "drained"}, &C::drainage), "-",
       "constant-volume: height held, r_u = (sigma_v0 - sigma_v) / sigma_v0; drained: vertical stress held by the servo"},
      {"direction_deg", &C::direction_deg, "deg", "direction of the sine, the ellipse's major axis, the figure-8's long axis, from +x towards +y", -360.0, 360.0},
      {"csr", &C::csr, "-", "cyclic stress ratio: shear stress amplitude / sigma'_v0 (control = stress)", 0.0, 2.0, true},
      {"strain_amplitude", &C::strain_amplitude, "-", "shear strain amplitude (control = strain)", 0.0, 0.5, true},
      {"minor_ratio", &C::minor_ratio, "-", "ellipse minor / major axis; figure-8 transverse amplitude / amplitude", 0.0, 10.0},
      {"series_file", &C::series_file, "-", "CSV of the series path: columns cycle (or time, s), x, y in CSR (stress) or strain"},
      {"period", &C::period, "s", "duration of one cycle; 0: 4 x 0.01 / the shear rate of shear.inertial_number (a quarter cycle at the monotonic rate per 1 % strain)", 0.0},
      {"static_csr", &C::static_csr, "-", "static shear stress / sigma'_v0 applied (over a quarter period, then held) before the cycles; 0: none", 0.0, 2.0},
      {"static_direction_deg", &C::static_direction_deg, "deg", "direction of the static shear stress", -360.0, 360.0},
      {"max_cycles", &C::max_cycles, "-", "cycles that end the test", 1.0, 100000.0},
      {"ru_limit", &C::ru_limit, "-", "excess pore pressure ratio r_u that ends the test (its cycle is N_L by r_u); 0: not a criterion", 0.0, 1.0},
      {"da_strain_limit", &C::da_strain_limit, "-", "double-amplitude shear strain over the last cycle that ends the test (N_L by strain); 0: not a criterion", 0.0, 2.0},
      {"rows_per_cycle", &C::rows_per_cycle, "-", "history rows per cycle (loops are drawn from them)", 4.0, 10000.0},
      {"post_strain", &C::post_strain, "-", "monotonic shear strain after the cycles, strain-controlled at the shear rate; 0: none", 0.0, 2.0},
      {"post_direction_deg", &C::post_direction_deg, "deg", "direction of the post-cyclic shear", -360.0, 360.0},
      {"servo_relaxation", &C::servo_relaxation, "-", "stress control: fraction of the shear stress error the top plate removes per step (gain alpha A / (sum k_s dt))", 0.0, 1.0, true},
      {"servo_max_speed", &C::servo_max_speed, "m/s", "stress control: speed cap of the top plate; 0: 10 x the shear rate x H_c", 0.0},
      {"snapshot_cycles", &C::snapshot_cycles, "-", "cycles N at which snapshots are written (cyclic_snapshots/)", 0.0},
      {"fabric_cycles", &C::fabric_cycles, "-", "cycles N at which the fabric is recorded (cyclic_fabric.csv)", 0.0},
  };
  return table;
}

std::string number_text(double v) {
  char text[32];
  for (int digits = 6; digits <= 17; ++digits) {  // the shortest text that reads back exactly
    std::snprintf(text, sizeof text, "%.*g", digits, v);
    if (std::stod(text) == v) break;
  }
  return text;
}

std::string list_text(const std::vector<double>& values) {
  std::string out;
  for (double v : values) out += (out.empty() ? "" : ",") + number_text(v);
  return out;
}

}  // namespace

void add_cyclic_shear_keys(io::Schema& schema) {
  const C defaults;
  for (const Binding& b : bindings()) {
    io::KeySpec spec{.key = "cyclic." + b.name, .unit = b.unit, .help = b.help, .min = b.min, .max = b.max,
                     .min_exclusive = b.min_exclusive};
    std::visit(
        [&](const auto& m) {
          using M = std::decay_t<decltype(m)>;
          if constexpr (std::is_same_v<M, double C::*>) spec.type = io::ValueType::Real, spec.default_value = number_text(defaults.*m);
          else if constexpr (std::is_same_v<M, long C::*>) spec.type = io::ValueType::Integer, spec.default_value = std::to_string(defaults.*m);
          else if constexpr (std::is_same_v<M, std::string C::*>) spec.type = io::ValueType::Text, spec.default_value = defaults.*m;
          else if constexpr (std::is_same_v<M, std::vector<double> C::*>) spec.type = io::ValueType::RealList, spec.default_value = list_text(defaults.*m);
          else spec.type = io::ValueType::Text, spec.default_value = m.get(defaults), spec.choices = m.choices;
        },
        b.member);
    schema.add(spec);
  }
}

io::Schema cyclic_shear_schema() {
  io::Schema schema = simple_shear_schema();
  add_cyclic_shear_keys(schema);
  return schema;
}

CyclicShearConfig cyclic_shear_config(const io::Config& config) {
  C c;
  for (const Binding& b : bindings()) {
    const std::string key = "cyclic." + b.name;
    std::visit(
        [&](const auto& m) {
          using M = std::decay_t<decltype(m)>;
          if constexpr (std::is_same_v<M, double C::*>) c.*m = config.real(key);
          else if constexpr (std::is_same_v<M, long C::*>) c.*m = config.integer(key);
          else if constexpr (std::is_same_v<M, std::string C::*>) c.*m = config.text(key);
          else if constexpr (std::is_same_v<M, std::vector<double> C::*>) c.*m = config.real_list(key);
          else m.set(c, config.text(key));
        },
        b.member);
  }
  require(c.path != CyclicShape::Series || !c.series_file.empty(), "cyclic.series_file", "(empty)",
          "a CSV file when cyclic.path = series");
  require(c.path == CyclicShape::Series || c.series_file.empty(), "cyclic.series_file", c.series_file,
          "empty unless cyclic.path = series (the file would be ignored)");
  require(c.ru_limit > 0 || c.da_strain_limit > 0 || c.max_cycles > 0, "cyclic stop criteria", "none", "at least one");
  return c;
}

}  // namespace dem::lab
