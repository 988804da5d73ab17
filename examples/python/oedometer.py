#!/usr/bin/python3
"""A custom protocol in Python: K0 loading and unloading in an oedometer. Balls fill a rigid
cylinder; a servo top plate loads them to 50, 100, 200 kPa and unloads to 50 kPa, and at each
stage the script reads the lateral stress from the cylinder wall: K0 = sigma_h / sigma_v. K0 of
the unloading is larger than of the loading at the same stress, as for an overconsolidated sand.

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/oedometer.py [out.csv]
"""

import sys

import numpy as np

import libdem

radius, height = 6e-3, 12e-3  # m, of the cell
world = libdem.World()        # local damping 0.7, automatic time step

# Balls of 0.8-1.2 mm diameter on a jittered lattice inside the cylinder, loose.
rng = np.random.default_rng(7)
grid = np.mgrid[-5:6, -5:6, 0:11].reshape(3, -1).T * 1.05e-3 + [0, 0, 0.6e-3]
inside = grid[np.hypot(grid[:, 0], grid[:, 1]) < radius - 0.6e-3]
world.add_balls(inside + rng.uniform(-2e-5, 2e-5, inside.shape), rng.uniform(0.4e-3, 0.5e-3, len(inside)), 2650.0)

bottom = world.add_wall("bottom", libdem.make_disc([0, 0, 0], radius, [0, 0, -1], 48), [0, 0, -1])
top = world.add_wall("top", libdem.make_disc([0, 0, height], radius, [0, 0, 1], 48), [0, 0, 1])
shell = world.add_wall("shell", libdem.make_cylinder_shell([0, 0, -1e-3], radius, height + 2e-3, 48, True), [1, 0, 0])
sand = libdem.RollingLinearParams.deformable(1e8, 1.0, 0.5, 0.1)
world.set_contact_model(libdem.ContactKind.BALL_BALL, sand, "ball-ball")
world.set_contact_model(libdem.ContactKind.BALL_FACET, libdem.RollingLinearParams.deformable(1e8, 1.0, 0.0, 0.0), "ball-facet")
servo = world.add_servo_wall(top.id, libdem.ServoSettings(target_stress=50e3, max_speed=0.05, settle_steps=500))

rows = []
print(f"{'sigma_v [kPa]':>13} {'sigma_h [kPa]':>13} {'K0':>6} {'porosity':>8}  stage")
for stage, target in (("load", 50e3), ("load", 100e3), ("load", 200e3), ("unload", 100e3), ("unload", 50e3)):
    servo.set_target(target)
    world.run_until(lambda w: servo.settled and w.unbalanced_force_ratio() < 0.01, 100, 400000)
    # The shell's outward normal is not one direction: its radial push is |F| summed over the
    # contacts, taken from the contact list, over the lateral area in contact with sand.
    c = world.contacts()
    on_shell = (c["kind"] == int(libdem.ContactKind.BALL_FACET)) & (c["second"] == shell.id)
    sample_height = height + top.displacement[2] - bottom.displacement[2]
    sigma_h = np.linalg.norm(c["force"][on_shell][:, :2], axis=1).sum() / (2 * np.pi * radius * sample_height)
    sigma_v = top.normal_stress
    solid = (4 / 3 * np.pi * world.radii**3).sum()
    porosity = 1 - solid / (np.pi * radius**2 * sample_height)
    rows.append((sigma_v, sigma_h, sigma_h / sigma_v, porosity))
    print(f"{sigma_v / 1e3:13.1f} {sigma_h / 1e3:13.1f} {sigma_h / sigma_v:6.3f} {porosity:8.4f}  {stage}")

out = sys.argv[1] if len(sys.argv) > 1 else "oedometer.csv"
np.savetxt(out, np.array(rows), delimiter=",", header="sigma_v,sigma_h,k0,porosity", comments="")
print(f"wrote {out}")
