#!/usr/bin/python3
"""K0 loading to 50, 100, 200 kPa in a ring stack, then constant-volume simple shear, from the lab
toolkit's parts: the twin of examples/k0_constant_volume.cpp (same seed, parts, order: same numbers).
Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/k0_constant_volume.py [out.csv [strain]]
"""

import sys

import numpy as np

import libdem as dem

out = sys.argv[1] if len(sys.argv) > 1 else "k0_constant_volume.csv"
final_strain = float(sys.argv[2]) if len(sys.argv) > 2 else 0.15
world = dem.World()  # local damping 0.7, automatic time step

spec = dem.ShearCellSpec()  # 20 mm x 8 mm, rings of 1.4 mm pebbles that follow the height
spec.diameter, spec.height, spec.pebble_diameter, spec.ring_gap, spec.max_opening = 0.02, 0.008, 1.4e-3, 7e-5, 1.4e-3
spec.rings = dem.RingVertical.FOLLOW
cell = dem.build_shear_cell(world, spec)


def set_law(kind, modulus, mu, mu_r):  # E* Pa, kn/ks 1, no dashpots
    world.set_contact_model(kind, dem.RollingLinearParams.deformable(modulus, 1.0, mu, mu_r), "law")


for kind in (dem.ContactKind.BALL_BALL, dem.ContactKind.BALL_FACET, dem.ContactKind.BALL_PEBBLE):
    set_law(kind, 1.2e7 if kind == dem.ContactKind.BALL_BALL else 2e7, 0.0, 0.0)  # frictionless growth

grading, rng = dem.Grading(), dem.Random(7)
grading.scale = 2.0  # 1.4-2.4 mm
diameters = dem.sample_diameters(grading, (1 - 0.40) * cell.area * spec.height, rng)
expansion = dem.add_expanding_balls(world, dem.Cylinder(cell.radius, spec.height), diameters, 2650.0, 4, rng)

state = {"servo": None, "made": False, "shearing": False}


def control(w):  # the servo (once there is one), the rings and the damping frame read the plates
    if state["servo"] is not None:
        state["servo"](w)
    dem.move_rings(w, cell, state["made"])
    if state["shearing"]:  # damped against uniform shear between the plates (docs/model.md 3.1)
        w.set_damping_frame(dem.plate_damping_frame(w, cell))


world.add_controller(control)
for stage in range(1, expansion.stages + 1):
    for increment in range(1, expansion.increments + 1):
        dem.set_radii(world, expansion, expansion.factor(stage, increment))
        world.step(expansion.steps_per_increment)
    world.run_until(lambda w: w.unbalanced_force_ratio() < 1e-2, 100, 20000)
state["made"] = True
dem.release_rings(world, cell)

set_law(dem.ContactKind.BALL_BALL, 1.2e7, 0.5, 0.1)
set_law(dem.ContactKind.BALL_FACET, 2e7, 0.9, 0.9)
set_law(dem.ContactKind.BALL_PEBBLE, 2e7, 0.1, 0.1)
servo = state["servo"] = dem.ServoWall(cell.top, dem.ServoSettings(50e3, 0.05, settle_steps=300))
for stress in (50e3, 100e3, 200e3):
    target = dem.ConsolidationTarget(stress, max_steps=200000)
    dem.start_consolidation(servo, target)
    report = dem.consolidate(world, servo, target, world.step_count)
    print(f"sigma_v {report.stress / 1e3:.2f} kPa  K0 {dem.ring_lateral_stress(world, cell) / report.stress:.3f}  "
          f"settled {report.settled}")

height = cell.plate_gap(world)
strain_rate = 1e-3 / (0.5 * (grading.smallest() + grading.largest()) * np.sqrt(2650.0 / 200e3))  # I = 1e-3
dem.start_shear_leg(world, cell, servo, dem.ShearLegMotion(0.0, strain_rate * height, dem.ShearMode.CONSTANT_VOLUME))
path, state["shearing"] = dem.ShearPath(world, cell, height), True
rows, steps_per_row = [], int(0.005 / strain_rate / world.time_step)
while path.strain < final_strain:
    world.step(steps_per_row)
    path.advance(world, cell)
    tau, sigma_v = world.wall(cell.top).force[0] / cell.area, world.wall(cell.top).normal_stress
    rows.append([path.strain, tau, sigma_v, tau / sigma_v, cell.plate_gap(world)])
dem.stop_shear(world, cell)
np.savetxt(out, rows, delimiter=",", fmt="%.17g", comments="",
           header="shear_strain,shear_stress_Pa,vertical_stress_Pa,stress_ratio,height_m")
print(f"tau/sigma_v at {100 * path.strain:.1f} %: {rows[-1][3]:.3f}; wrote {out}")
