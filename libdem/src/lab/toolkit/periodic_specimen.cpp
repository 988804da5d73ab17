// The periodic specimen: a seeded gas of balls in a cubic cell, compressed by the cell servo to an
// isotropic stress with the compaction friction (lab/toolkit/periodic_specimen.hpp).
#include <dem/lab/toolkit/periodic_specimen.hpp>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <ostream>
#include <random>
#include <sstream>

#include <dem/boundary/periodic_cell.hpp>
#include <dem/core/errors.hpp>
#include <dem/core/world.hpp>
#include <dem/measure/cell_stress.hpp>

namespace dem::lab {

namespace {

constexpr long check_every_steps = 100;  // steps between tests of the end state
constexpr int placing_trials = 100000;   // random positions tried for one ball

double sphere_volume(double diameter) { return std::numbers::pi / 6.0 * diameter * diameter * diameter; }

}  // namespace

void fill_periodic_cell(World& world, const PeriodicSpecimenSettings& s) {
  require(s.balls >= 2, s.section + ".balls", s.balls, ">= 2");
  s.grading.validate("grading");
  require(s.initial_solid_fraction > 0.0 && s.initial_solid_fraction < 0.5, s.section + ".initial_solid_fraction", s.initial_solid_fraction, "in (0, 0.5)");
  std::mt19937_64 rng(s.seed);
  // More volume than `balls` of the largest size: the draw yields at least that many diameters.
  std::vector<double> diameters = sample_diameters(s.grading, static_cast<double>(s.balls + 1) * sphere_volume(s.grading.largest()), rng);
  diameters.resize(static_cast<std::size_t>(s.balls));
  double solid = 0.0;  // m^3
  for (double d : diameters) solid += sphere_volume(d);
  const double edge = std::cbrt(solid / s.initial_solid_fraction);  // m
  std::sort(diameters.begin(), diameters.end(), std::greater<>());   // the largest find room first
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<Vec3> placed;
  std::vector<double> radii;
  for (double d : diameters) {
    const double r = d / 2;
    int trial = 0;
    for (;; ++trial) {
      require(trial < placing_trials, s.section + ".initial_solid_fraction", s.initial_solid_fraction,
              "low enough that random placing finds room for every ball (0.3 does)");
      const Vec3 x = edge * Vec3(unit(rng), unit(rng), unit(rng));
      bool free = true;
      for (std::size_t k = 0; k < placed.size() && free; ++k) {
        Vec3 gap = x - placed[k];
        for (int a = 0; a < 3; ++a) gap[a] -= edge * std::round(gap[a] / edge);  // the nearest image
        free = gap.norm() > r + radii[k];
      }
      if (!free) continue;
      placed.push_back(x);
      radii.push_back(r);
      BallSpec ball;
      ball.position = x;
      ball.radius = r;
      ball.density = s.density;
      world.add_ball(ball);
      break;
    }
  }
  world.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(edge)));
}

bool isotropic_state_reached(const World& world, double stress, double tolerance, double equilibrium_ratio) {
  const Mat3 sigma = -measure::cell_stress(world).stress;  // compression positive
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      const double target = a == b ? stress : 0.0;
      if (!(std::abs(sigma(a, b) - target) <= tolerance * stress)) return false;
    }
  return world.unbalanced_force_ratio() < equilibrium_ratio;
}

PeriodicSpecimen::PeriodicSpecimen(Run& run, PeriodicSpecimenSettings settings) : run_(run), settings_(std::move(settings)) {
  World& w = run_.world();
  w.set_periodic_cell(PeriodicCell::box(Vec3::Zero(), Vec3::Constant(1.0)));  // until placed or loaded
  CellServoSettings isotropic = CellServoSettings::isotropic(settings_.stress, settings_.max_rate);
  for (std::size_t a = 3; a < 6; ++a) isotropic.stress_controlled[a] = true;  // shear stresses held at 0
  servo_ = add_cell_servo(w, isotropic);
  w.set_contact_model(ContactKind::BallBall, settings_.ball_ball.model_with_friction(settings_.compaction_friction, 0.0, "ball_ball"));
  run_.keep("specimen_stage", [this] { return static_cast<double>(stage_); }, [this](double v) {
    require(v >= 0 && v <= 2 && v == std::floor(v), "restart file: specimen_stage", v, "0, 1 or 2");
    stage_ = static_cast<Stage>(static_cast<int>(v));
  });
  run_.keep("specimen_stage_start_step", stage_start_step_);
}

void PeriodicSpecimen::use_material_law(bool keep_contacts) {
  World& w = run_.world();
  if (keep_contacts) w.retune_contact_model(ContactKind::BallBall, settings_.ball_ball.model("ball_ball"));
  else w.set_contact_model(ContactKind::BallBall, settings_.ball_ball.model("ball_ball"));
}

void PeriodicSpecimen::place() {
  World& w = run_.world();
  if (stage_ == Stage::Empty) {
    fill_periodic_cell(w, settings_);
    stage_ = Stage::Compressing;
    stage_start_step_ = w.step_count();
    run_.log() << "placed " << w.particles().size() << " balls in a cubic cell of edge " << w.periodic_cell()->matrix()(0, 0) * 1e3
               << " mm (solid fraction " << settings_.initial_solid_fraction << ")\n";
  }
}

void PeriodicSpecimen::run(const std::function<void()>& after_chunk) {
  World& w = run_.world();
  place();
  if (stage_ == Stage::Compressing) {
    const PeriodicSpecimenSettings& s = settings_;
    while (w.step_count() == stage_start_step_ || !isotropic_state_reached(w, s.stress, s.tolerance, s.equilibrium_ratio)) {
      if (w.step_count() - stage_start_step_ >= s.max_steps) {
        run_.log() << "warning: the isotropic compression did not reach " << s.stress << " Pa within max_steps = " << s.max_steps << "\n";
        break;
      }
      w.step(check_every_steps);
      if (after_chunk) after_chunk();
      run_.save_if_due();  // after the chunk's rows: a resume goes on with the next chunk
      const Vec3 normal = -measure::cell_stress(w).stress.diagonal();
      std::ostringstream detail;
      detail << "step " << w.step_count() << ", normal stresses " << normal.x() / 1e3 << ", " << normal.y() / 1e3 << ", "
             << normal.z() / 1e3 << " kPa of " << s.stress / 1e3 << ", unbalanced ratio " << w.unbalanced_force_ratio();
      run_.progress("compression", detail.str());  // its end is an equilibrium: no time left to tell
    }
    stage_ = Stage::Done;
    run_.log() << "isotropic compression done at step " << w.step_count() << ": cell edges " << w.periodic_cell()->matrix()(0, 0) * 1e3
               << ", " << w.periodic_cell()->matrix()(1, 1) * 1e3 << ", " << w.periodic_cell()->matrix()(2, 2) * 1e3 << " mm, time step "
               << w.time_step() << " s\n";
  }
}

}  // namespace dem::lab
