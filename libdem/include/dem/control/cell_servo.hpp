// Mixed stress and strain-rate control of a periodic cell (boundary/periodic_cell.hpp): each of the
// six components of the cell's velocity gradient that an element test drives (xx yy zz, and the
// shears yz xz xy as the upper triangle of L, so that an upper-triangular cell stays one, as
// LAMMPS's triclinic box) is either prescribed as a rate or set every step by a servo so that
// the matching cell stress (measure/cell_stress.hpp, compression positive here) approaches a
// target. The lower triangle of L is zero: the cell does not spin (docs/model.md 13).
//
// The gain rule follows the servo wall's (control/servo_wall.hpp, docs/model.md 5): a strain
// increment de_ab of the cell moves an affine packing's stress by K_ab de_ab, with
//
//   K_ab = (1 / V) sum_c k_n |d_c|^2 n_a^2 n_b^2      (normal springs of the touching contacts),
//
// so L_ab = -relaxation (s*_ab - s_ab) / (K_ab dt) removes that fraction of the error in one step
// if the particles followed the cell. Capped at max_rate (1/s): a loose packing (K small, or no
// contacts) is approached at the cap. The shear springs make the packing stiffer than K, so a
// relaxation up to 0.5 leaves room (the loop is stable while the true stiffness is below 2 / relaxation
// times K). Peri3dController and geoLAMMPS's fix multistress use the same kind of rule.
//
// The servo reads contacts during the step: add_cell_servo sets World::ContactRecords::EveryStep.
//
// Typical use (isotropic compression to 100 kPa, then drained triaxial compression along z):
//   auto servo = dem::add_cell_servo(world, dem::CellServoSettings::isotropic(100e3, 1.0));
//   world.run_until([&](const dem::World&) { return servo->settled(); }, 100, 1'000'000);
//   servo->set_rate(dem::CellComponent::zz, -0.01);   // 1/s, shortening; xx yy keep their stress
//
// A target may follow a path in time (set_stress_path, set_rate_path: the cyclic shear's paths
// and CSV series are such functions), and one normal component may keep the volume instead
// (hold_volume: its rate is minus the sum of the other two, so tr L = 0, which the cell's
// exponential step keeps to rounding). Not here yet: constant mean stress as a path of its own.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <string>

#include <dem/core/math.hpp>
#include <dem/measure/cell_stress.hpp>

namespace dem {

class World;

/// The six controlled components, in Voigt order.
enum class CellComponent { xx = 0, yy = 1, zz = 2, yz = 3, xz = 4, xy = 5 };
/// Each component's (row, column) in L and in the stress.
inline constexpr std::array<std::array<int, 2>, 6> cell_component_index{{{0, 0}, {1, 1}, {2, 2}, {1, 2}, {0, 2}, {0, 1}}};
const char* to_string(CellComponent component);

struct CellServoSettings {
  /// Per component: true where the stress is held, false where the rate is prescribed.
  std::array<bool, 6> stress_controlled{};
  /// Per component: the stress to hold (Pa, compression positive) or the rate L_ab (1/s).
  std::array<double, 6> target{};
  double relaxation = 0.5;  // -, in (0, 1]: fraction of a stress error removed per step
  double max_rate = 0.0;    // 1/s, > 0 (required): cap on a stress-controlled component's |L_ab|
  double settle_tolerance = 0.01;  // -, |s - s*| <= this x max(|s*|, mean target stress) counts as held
  int settle_steps = 100;          // steps, >= 1: consecutive held steps for settled()

  /// The normal stresses held at `stress` (Pa, compression positive), no shear, at most
  /// `max_rate` (1/s).
  static CellServoSettings isotropic(double stress, double max_rate);
  /// InputError naming `where`.<key>, the value and the allowed range.
  void validate(const std::string& where = "cell servo") const;
};

/// A World controller that sets the periodic cell's velocity gradient every step (see above).
class CellServo {
 public:
  explicit CellServo(CellServoSettings settings);
  /// One control step: the cell stress of this step's contacts, then L. InputError without a cell.
  void operator()(World& world);

  /// Holds `component` at `stress` (Pa, compression positive) from the next step on.
  void set_stress(CellComponent component, double stress);
  /// Prescribes `component`'s rate L_ab (1/s) from the next step on.
  void set_rate(CellComponent component, double rate);
  /// The same with a target that follows the World's time (s): evaluated every step, it must
  /// return a finite value (else InputError at that step).
  void set_stress_path(CellComponent component, std::function<double(double time)> stress);
  void set_rate_path(CellComponent component, std::function<double(double time)> rate);
  /// The normal component (xx, yy or zz) whose rate keeps the cell's volume: minus the sum of the
  /// other two normal rates. InputError for a shear component.
  void hold_volume(CellComponent normal);
  const CellServoSettings& settings() const { return settings_; }

  /// The cell stress of the last step (tension positive, as measure::cell_stress).
  const measure::CellStress& stress() const { return stress_; }
  /// The stiffness K_ab of the last step (Pa), per component.
  const std::array<double, 6>& stiffness() const { return stiffness_; }
  /// Every stress-controlled component held within settle_tolerance for settle_steps steps.
  bool settled() const { return steps_held_ >= settings_.settle_steps; }

 private:
  enum class Mode { rate, stress, volume };
  /// Sets `component`'s mode and clears its path.
  void set_mode(CellComponent component, Mode mode);

  CellServoSettings settings_;
  std::array<Mode, 6> mode_{};
  std::array<std::function<double(double)>, 6> path_;  // empty: the constant settings_.target
  measure::CellStress stress_;
  std::array<double, 6> stiffness_{};
  int steps_held_ = 0;
};

/// Makes a CellServo, registers it as a controller of `world` and sets the contact records to
/// every step. InputError without a periodic cell or for invalid settings.
std::shared_ptr<CellServo> add_cell_servo(World& world, const CellServoSettings& settings);

}  // namespace dem
