// What a simple-shear configuration makes, as toolkit parts: the world's settings, the cell, the
// contact laws, the specimen's diameters and the servo of the consolidation. SimpleShearTest is
// built from these, and so is a protocol written as a script (examples/ngi_simple_shear.cpp), so
// that both make the same specimen from the same keys.
#pragma once

#include <random>
#include <vector>

#include <dem/contact/linear_law.hpp>
#include <dem/control/servo_wall.hpp>
#include <dem/core/world.hpp>
#include <dem/lab/shear_cell.hpp>
#include <dem/lab/simple_shear_config.hpp>

namespace dem::lab {

/// engine.*: damping, time step and its safety factor, overlap limit, threads.
WorldSettings world_settings(const SimpleShearConfig& config);

/// The cell of specimen.* and rings.*: pebbles of rings.pebble_diameter (or the smallest ball),
/// gaps of rings.gap (or 5 % of a pebble), a stack of rings.stack_height (or the specimen height;
/// 1.1 times it for fixed rings, which cannot follow a dilating specimen), openings smaller than
/// the smallest ball.
ShearCellSpec shear_cell_spec(const SimpleShearConfig& config);

/// The rolling-resistance linear law of a contact type with the given friction coefficients.
RollingLinearLaw::Params contact_law(const ContactTypeConfig& contact, double friction, double rolling_friction);

/// Whether a model change rebuilds the contact lists (a new law: their history starts fresh) or
/// keeps them (the same laws with new parameters, World::retune_contact_model).
enum class ModelChange { Rebuild, KeepContacts };

/// Sets the three contact kinds: ball-ball with the given friction, the plates and rings with
/// their own (frictionless while `growing`, so that the radius expansion packs the specimen).
void set_contact_laws(World& world, const SimpleShearConfig& config, double friction, double rolling_friction, bool growing,
                      ModelChange change = ModelChange::Rebuild);

/// The specimen's diameters for specimen.porosity in the cylinder, drawn from `rng` (the test
/// seeds it with specimen.seed, then places the balls with the same generator).
std::vector<double> specimen_diameters(const SimpleShearConfig& config, std::mt19937_64& rng);

/// The top plate's servo for consolidation.*: the target stress, its relaxation, speed cap,
/// settle tolerance and steps.
ServoSettings consolidation_servo(const SimpleShearConfig& config);

}  // namespace dem::lab
