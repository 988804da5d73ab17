// Guards of a specimen in a shear cell: balls that left it, and a loaded restart file's specimen
// and engine keys against this run's configuration.
#include <dem/lab/toolkit/specimen_guards.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <sstream>

#include <dem/core/errors.hpp>

namespace dem::lab {

namespace {

struct Escape {
  std::size_t index = 0;
  double radial_excess = 0.0;  // m, beyond the ring's inner radius plus a pebble radius
  double above_top = 0.0;      // m, above the top plate
  double below_bottom = 0.0;   // m, below the bottom plate
};

// The ring whose mid-height is nearest to z (rings are stacked bottom first).
const Clump& ring_at(const std::vector<Clump>& rings, double z) {
  std::size_t best = 0;
  for (std::size_t k = 1; k < rings.size(); ++k)
    if (std::abs(rings[k].x.z() - z) < std::abs(rings[best].x.z() - z)) best = k;
  return rings[best];
}

std::vector<Escape> escapes(const World& w, const ShearCell& cell) {
  std::vector<Escape> out;
  const ParticleStore& p = w.particles();
  const double z_bottom = w.wall(cell.bottom).displacement.z(), z_top = cell.built_height + w.wall(cell.top).displacement.z();
  const double inner_radius = cell.radius, pebble_radius = cell.pebble_radius;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i)) continue;
    const Vec3& x = p.x[i];
    Escape e;
    e.index = i;
    if (!w.clumps().empty()) {
      const Clump& ring = ring_at(w.clumps(), x.z());
      e.radial_excess = std::hypot(x.x() - ring.x.x(), x.y() - ring.x.y()) - (inner_radius + pebble_radius);
    } else {
      e.radial_excess = -1.0;
    }
    e.above_top = x.z() - z_top;
    e.below_bottom = z_bottom - x.z();
    if (e.radial_excess > 0 || e.above_top > 0 || e.below_bottom > 0) out.push_back(e);
  }
  return out;
}

}  // namespace

std::size_t balls_outside(const World& world, const ShearCell& cell) { return escapes(world, cell).size(); }

void require_no_escape(const World& world, const ShearCell& cell, double shear_strain) {
  const std::vector<Escape> out = escapes(world, cell);
  if (out.empty()) return;
  const Escape& e = out.front();
  const ParticleStore& p = world.particles();
  const Vec3& x = p.x[e.index];
  std::ostringstream msg;
  msg.precision(6);
  msg << out.size() << " ball(s) left the specimen by step " << world.step_count() << " (t = " << world.time()
      << " s, shear strain " << shear_strain << "); the first, ball id " << p.id[e.index] << ", is at (" << x.x() << ", "
      << x.y() << ", " << x.z() << ") m: ";
  double stack_top = -std::numeric_limits<double>::infinity();
  for (const Clump& ring : world.clumps())
    for (ParticleId pid : ring.pebbles) stack_top = std::max(stack_top, p.x[p.index_of(pid)].z() + cell.pebble_radius);
  if (e.above_top > 0 || e.below_bottom > 0)
    msg << (e.above_top > 0 ? "above the top plate" : "below the bottom plate")
        << ": it passed through a plate (too large a time step or too soft a ball-facet contact for the stress)";
  else if (x.z() > stack_top - 2 * cell.pebble_radius)
    msg << "beyond the rings at height " << x.z() << " m, the ring stack reaches " << stack_top
        << " m: it escaped over the top ring (a dilating specimen above a stack that does not follow it: "
        << "rings.vertical = follow, or a taller rings.stack_height)";
  else
    msg << "beyond the ring wall by " << e.radial_excess << " m: it passed between pebbles or rings (openings wider "
        << "than the smallest ball: a smaller rings.gap or rings.pebble_diameter)";
  throw InstabilityError(msg.str());
}

// A restart file holds the world as it was made: the engine settings, the balls' and rings'
// masses, the walls and rings as built. Keys that only set up the engine are applied again from
// this run's configuration; keys that describe the specimen itself are refused when they differ,
// since the specimen cannot be remade from the file.
void apply_restart_keys(World& world, const World& as_configured, const ShearCell& cell, const SimpleShearConfig& config,
                        const std::filesystem::path& file, std::ostream& log) {
  const std::string where = "restart file " + file.string() + ": ";
  WorldSettings saved = world.settings();
  if (saved.local_damping != config.engine.local_damping) {
    world.set_local_damping(config.engine.local_damping);
    log << "applied engine.local_damping = " << config.engine.local_damping << " (the restart file had " << saved.local_damping << ")\n";
  }
  require(saved.time_step_safety == config.engine.time_step_safety, where + "engine.time_step_safety", config.engine.time_step_safety,
          "the file's value, " + std::to_string(saved.time_step_safety) + " (the time step of a running specimen is set by engine.time_step)");
  if (saved.time_step != config.engine.time_step) {
    if (config.engine.time_step > 0) {
      world.set_time_step(config.engine.time_step);
    } else {
      require(false, where + "engine.time_step", config.engine.time_step,
              "the file's fixed step, " + std::to_string(saved.time_step) + " s, or another fixed step > 0 (0, automatic, "
              "would re-estimate the step mid-run)");
    }
    log << "applied engine.time_step = " << config.engine.time_step << " s (the restart file had " << saved.time_step << " s)\n";
  }
  // The configuration's limit, not the one of the run that wrote the file (older files hold 0.5).
  world.set_max_overlap_ratio(config.engine.max_overlap_ratio);

  // Balls: their density is part of the specimen (the first ball tells: all share one density).
  const ParticleStore& p = world.particles();
  std::size_t ball = 0;
  while (ball < p.size() && p.is_pebble(ball)) ++ball;
  if (ball < p.size()) {
    const double expected = config.specimen.density * 4.0 / 3.0 * pi * std::pow(p.radius[ball], 3);
    require(std::abs(p.mass[ball] - expected) <= 1e-9 * expected, where + "specimen.density", config.specimen.density,
            "the density the specimen was made with (" + std::to_string(p.mass[ball] / expected * config.specimen.density) +
                " kg/m^3)");
  }
  // Rings and plates as this configuration builds them: same count, pebbles and places.
  const auto& built = as_configured.clumps();
  auto& rings = world.clumps();
  const bool same_stack = built.size() == rings.size() && [&] {
    for (std::size_t k = 0; k < rings.size(); ++k)
      if (rings[k].pebbles.size() != built[k].pebbles.size() ||
          (rings[k].x - rings[k].displacement - built[k].x).norm() > 1e-9 * config.specimen.diameter)
        return false;
    return true;
  }();
  require(same_stack, where + "specimen.diameter, specimen.height, rings.pebble_diameter, rings.gap, rings.stack_height",
          "(as configured)", "the values the specimen was made with: resume with its configuration (the ring stack in the file differs)");
  const double file_height = world.wall(cell.top).reference_point.z() - world.wall(cell.top).displacement.z();
  require(std::abs(file_height - config.specimen.height) <= 1e-9 * config.specimen.height, where + "specimen.height", config.specimen.height,
          "the height the specimen was made with, " + std::to_string(file_height) + " m");
  for (std::size_t k = 0; k < rings.size(); ++k) {
    if (std::abs(rings[k].mass - built[k].mass) > 1e-12 * built[k].mass) {
      if (k == 0) log << "applied rings.density = " << config.rings.density << " kg/m^3 to the rings of the restart file\n";
      rings[k].mass = built[k].mass;
      rings[k].inertia_body = built[k].inertia_body;
      rings[k].inv_inertia_body = built[k].inv_inertia_body;
      ParticleStore& store = world.particles();
      for (ParticleId pid : rings[k].pebbles) store.inv_mass[store.index_of(pid)] = 1.0 / built[k].mass;
    }
  }
}

// A specimen resumed under another configuration would run with that configuration's contact
// parameters and rings without a word (a 2D specimen under the 4D defaults softens and collapses).
// Its ball sizes tell a different grading or size scale for certain.
void require_configured_grading(const World& world, const SimpleShearConfig& config, const std::filesystem::path& file) {
  const ParticleStore& p = world.particles();
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.is_pebble(i)) continue;
    smallest = std::min(smallest, 2 * p.radius[i]);
    largest = std::max(largest, 2 * p.radius[i]);
  }
  if (largest == 0.0) return;  // no balls yet
  const double tolerance = 1e-9;  // relative: the generation draws diameters inside the grading's range
  const double low = config.grading.smallest(), high = config.grading.largest();
  std::ostringstream found, allowed;
  found << smallest * 1e3 << "-" << largest * 1e3 << " mm";
  allowed << "within this run's grading, " << low * 1e3 << "-" << high * 1e3 << " mm (grading.scale = "
          << config.grading.scale << "): resume with the configuration the specimen was made with (the same --preset "
          << "and --config)";
  require(smallest >= low * (1 - tolerance) && largest <= high * (1 + tolerance),
          "restart file " + file.string() + ": ball diameters", found.str(), allowed.str());
}

}  // namespace dem::lab
