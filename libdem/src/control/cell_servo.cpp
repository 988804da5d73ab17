#include <dem/control/cell_servo.hpp>

#include <algorithm>
#include <cmath>

#include <dem/base/errors.hpp>
#include <dem/core/pair_geometry.hpp>
#include <dem/core/world.hpp>

namespace dem {

const char* to_string(CellComponent component) {
  static constexpr const char* names[] = {"xx", "yy", "zz", "yz", "xz", "xy"};
  return names[static_cast<int>(component)];
}

CellServoSettings CellServoSettings::isotropic(double stress, double max_rate) {
  CellServoSettings s;
  for (int a = 0; a < 3; ++a) s.stress_controlled[static_cast<std::size_t>(a)] = true, s.target[static_cast<std::size_t>(a)] = stress;
  s.max_rate = max_rate;
  return s;
}

void CellServoSettings::validate(const std::string& where) const {
  for (std::size_t a = 0; a < 6; ++a)
    require(std::isfinite(target[a]), where + ".target." + to_string(static_cast<CellComponent>(a)), target[a],
            stress_controlled[a] ? "finite (Pa, compression positive)" : "finite (1/s)");
  require(relaxation > 0.0 && relaxation <= 1.0, where + ".relaxation", relaxation, "in (0, 1]");
  require(std::isfinite(max_rate) && max_rate > 0.0, where + ".max_rate", max_rate, "finite and > 0 (1/s)");
  require(std::isfinite(settle_tolerance) && settle_tolerance >= 0.0, where + ".settle_tolerance", settle_tolerance,
          "finite and >= 0 (relative)");
  require(settle_steps >= 1, where + ".settle_steps", settle_steps, ">= 1 (steps)");
}

CellServo::CellServo(CellServoSettings settings) : settings_(settings) {
  settings_.validate();
  for (std::size_t a = 0; a < 6; ++a) mode_[a] = settings_.stress_controlled[a] ? Mode::stress : Mode::rate;
}

void CellServo::set_mode(CellComponent component, Mode mode) {
  const auto a = static_cast<std::size_t>(component);
  mode_[a] = mode;
  settings_.stress_controlled[a] = mode == Mode::stress;
  path_[a] = nullptr;
  steps_held_ = 0;
}

void CellServo::set_stress(CellComponent component, double stress) {
  require(std::isfinite(stress), std::string("cell servo target.") + to_string(component), stress,
          "finite (Pa, compression positive)");
  set_mode(component, Mode::stress);
  settings_.target[static_cast<std::size_t>(component)] = stress;
}

void CellServo::set_rate(CellComponent component, double rate) {
  require(std::isfinite(rate), std::string("cell servo target.") + to_string(component), rate, "finite (1/s)");
  set_mode(component, Mode::rate);
  settings_.target[static_cast<std::size_t>(component)] = rate;
}

void CellServo::set_stress_path(CellComponent component, std::function<double(double time)> stress) {
  require(static_cast<bool>(stress), std::string("cell servo stress path.") + to_string(component), "empty", "a callable");
  set_mode(component, Mode::stress);
  path_[static_cast<std::size_t>(component)] = std::move(stress);
}

void CellServo::set_rate_path(CellComponent component, std::function<double(double time)> rate) {
  require(static_cast<bool>(rate), std::string("cell servo rate path.") + to_string(component), "empty", "a callable");
  set_mode(component, Mode::rate);
  path_[static_cast<std::size_t>(component)] = std::move(rate);
}

void CellServo::hold_volume(CellComponent normal) {
  require(static_cast<int>(normal) < 3, "cell servo volume component", to_string(normal),
          "a normal component (xx, yy or zz)");
  for (std::size_t a = 0; a < 3; ++a)
    if (mode_[a] == Mode::volume) set_mode(static_cast<CellComponent>(a), Mode::rate);  // one at a time
  set_mode(normal, Mode::volume);
}

void CellServo::operator()(World& world) {
  const PeriodicCell* cell = world.periodic_cell();
  require(cell != nullptr, "cell servo", "on a World without a periodic cell", "on one with a cell (set_periodic_cell)");
  stress_ = measure::cell_stress(world);
  // K_ab from the normal stiffness of each touching ball-ball contact (the law's own).
  const ParticleStore& p = world.particles();
  const ContactModel* model = world.contact_model(ContactKind::BallBall);
  std::array<double, 6> moment{};  // N m, sum_c k_n |d|^2 n_a^2 n_b^2
  if (model != nullptr)
    world.for_each_contact([&](const ContactView& c) {
      if (c.kind != ContactKind::BallBall) return;
      const auto i = c.first, j = static_cast<std::size_t>(c.second);
      ContactKinematics k{};
      k.kind = c.kind;
      k.normal = c.normal;
      k.radius_1 = p.radius[i], k.radius_2 = p.radius[j];
      k.effective_radius = k.radius_1 * k.radius_2 / (k.radius_1 + k.radius_2);
      k.effective_mass = 1.0 / (p.inv_mass[i] + p.inv_mass[j]);
      const double kn = model->stiffness(k).normal;
      const double length_sq = branch(p.x.data(), i, j, c.image_shift).squaredNorm();
      for (std::size_t a = 0; a < 6; ++a) {
        const auto [r, s] = cell_component_index[a];
        moment[a] += kn * length_sq * c.normal[r] * c.normal[r] * c.normal[s] * c.normal[s];
      }
    });
  const double dt = world.time_step();
  for (std::size_t a = 0; a < 6; ++a)  // the paths' targets now
    if (path_[a]) {
      const double target = path_[a](world.time());
      require(std::isfinite(target), std::string("cell servo path.") + to_string(static_cast<CellComponent>(a)), target,
              "finite at every time");
      settings_.target[a] = target;
    }
  double scale = 0.0;  // Pa, the mean |target| of the stress-controlled normal components
  int normal_held = 0;
  for (std::size_t a = 0; a < 3; ++a)
    if (settings_.stress_controlled[a]) scale += std::abs(settings_.target[a]), ++normal_held;
  scale = normal_held > 0 ? scale / normal_held : 0.0;
  Mat3 gradient = Mat3::Zero();
  bool held = true;
  for (std::size_t a = 0; a < 6; ++a) {
    const auto [r, s] = cell_component_index[a];
    stiffness_[a] = moment[a] / stress_.volume;
    if (mode_[a] == Mode::volume) continue;  // below, once the other normal rates are known
    if (mode_[a] == Mode::rate) {
      gradient(r, s) = settings_.target[a];
      continue;
    }
    const double error = settings_.target[a] - (-stress_.stress(r, s));  // Pa, compression positive
    held = held && std::abs(error) <= settings_.settle_tolerance * std::max(std::abs(settings_.target[a]), scale);
    const double rate = stiffness_[a] > 0.0 && dt > 0.0 ? -settings_.relaxation * error / (stiffness_[a] * dt)
                                                        : (error > 0.0 ? -settings_.max_rate : settings_.max_rate);
    gradient(r, s) = std::clamp(rate, -settings_.max_rate, settings_.max_rate);
  }
  for (int a = 0; a < 3; ++a)
    if (mode_[static_cast<std::size_t>(a)] == Mode::volume) gradient(a, a) = -(gradient.trace() - gradient(a, a));
  steps_held_ = held ? steps_held_ + 1 : 0;
  world.set_velocity_gradient(gradient);
}

std::shared_ptr<CellServo> add_cell_servo(World& world, const CellServoSettings& settings) {
  require(world.periodic_cell() != nullptr, "cell servo", "on a World without a periodic cell",
          "on one with a cell (World::set_periodic_cell first)");
  auto servo = std::make_shared<CellServo>(settings);
  world.set_contact_records(World::ContactRecords::EveryStep);
  world.add_controller([servo](World& w) { (*servo)(w); });
  return servo;
}

}  // namespace dem
