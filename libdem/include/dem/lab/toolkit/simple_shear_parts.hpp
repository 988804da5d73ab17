// What the NGI cell's keys (lab/toolkit/simple_shear_config.hpp) make, as toolkit parts: the
// world's settings, the cell, the contact laws, the specimen's diameters, the servos, the shear
// rate and the plates' motion. NgiSpecimen and the protocols on it are built from these, so that
// every protocol makes the same specimen from the same keys.
#pragma once

#include <random>
#include <vector>

#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/toolkit/consolidation.hpp>
#include <dem/lab/toolkit/friction_schedule.hpp>
#include <dem/lab/toolkit/shear_cell.hpp>
#include <dem/lab/toolkit/simple_shear_config.hpp>

namespace dem::lab {

/// engine.*: damping, time step and its safety factor, overlap limit, threads.
WorldSettings world_settings(const EngineConfig& engine);
inline WorldSettings world_settings(const SimpleShearConfig& config) { return world_settings(config.engine); }

/// The cell of specimen.* and rings.*: pebbles of rings.pebble_diameter (or the smallest ball),
/// gaps of rings.gap (or 5 % of a pebble), a stack of rings.stack_height (or the specimen height;
/// 1.1 times it for fixed rings, which cannot follow a dilating specimen), openings smaller than
/// the smallest ball.
ShearCellSpec shear_cell_spec(const SimpleShearConfig& config);

/// Whether a model change rebuilds the contact lists (a new law: their history starts fresh) or
/// keeps them (the same laws with new parameters, World::retune_contact_model).
enum class ModelChange { Rebuild, KeepContacts };

/// Sets the three contact kinds: ball-ball with the given friction, the plates and rings with
/// their own (frictionless while `growing`, so that the radius expansion packs the specimen).
void set_contact_laws(World& world, const SimpleShearConfig& config, double friction, double rolling_friction,
                      bool growing, ModelChange change = ModelChange::Rebuild);

/// The specimen's diameters for specimen.porosity in the cylinder, drawn from `rng` (the test
/// seeds it with specimen.seed, then places the balls with the same generator).
std::vector<double> specimen_diameters(const SimpleShearConfig& config, std::mt19937_64& rng);

/// The top plate's servo for consolidation.*: the target stress, its relaxation, speed cap,
/// settle tolerance and steps.
ServoSettings consolidation_servo(const SimpleShearConfig& config);

/// The top plate's servo while the radii grow: consolidation_servo() on generation.stress with
/// generation.servo_max_speed.
ServoSettings generation_servo(const SimpleShearConfig& config);

/// The friction schedule of the generation (generation.*): to specimen.porosity, the generation
/// friction reduced by generation.friction_reduction per step, zero below 1 % of it.
FrictionSchedule generation_friction_schedule(const SimpleShearConfig& config);

/// The consolidation's target (consolidation.*, settled when the unbalanced ratio is below
/// generation.equilibrium_ratio), checked every `chunk_steps`.
ConsolidationTarget consolidation_target(const SimpleShearConfig& config, std::int64_t chunk_steps);

/// Mean diameter of the balls in the world (m; pebbles not counted), `fallback` without balls.
double mean_ball_diameter(const World& world, double fallback);

/// The shear strain rate (1/s): shear.strain_rate, or the rate at which the inertial number
/// I = gamma_dot d_mean sqrt(rho / sigma_v) is shear.inertial_number (docs/model.md 3.4), with
/// d_mean the mean diameter of the balls in the world.
double shear_strain_rate(const SimpleShearConfig& config, const World& world);

/// The cap on the top plate's vertical speed while shearing (m/s): shear.servo_max_speed, or the
/// faster of the consolidation's cap and the shear speed `rate` x `height`.
double shear_servo_speed(const SimpleShearConfig& config, double rate, double height);

/// The plates' motion for a shear leg in `direction_deg` at the strain rate `rate` (1/s) of a
/// specimen of height `height` (m): shear.mode, shear.moving_plate and shear_servo_speed().
ShearLegMotion shear_leg_motion(const SimpleShearConfig& config, double direction_deg, double rate, double height);

/// The damping frame while the plates shear, as shear.damping_frame says: the plates' affine field
/// (plate_damping_frame) or the fixed frame. Set it every step of the shear (a controller's job).
DampingFrame shear_damping_frame(const SimpleShearConfig& config, const World& world, const ShearCell& cell);

}  // namespace dem::lab
