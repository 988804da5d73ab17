#!/usr/bin/python3
"""The smallest libdem program in Python: 600 balls poured into an open box under gravity, with
the kinetic energy printed as the pile settles (examples/hello_pour.cpp, from Python).

Run: .venv/bin/python examples/python/pour.py [steps per line] (the package installed as the README's
"From Python" says), or PYTHONPATH=build/python /usr/bin/python3 examples/python/pour.py
"""

import sys

import numpy as np

import libdem

settings = libdem.WorldSettings()
settings.gravity = [0.0, 0.0, -9.81]  # m/s^2
settings.local_damping = 0.3          # some damping, so that the pile comes to rest
world = libdem.World(settings)

# 600 balls of 0.8-1.2 mm diameter on a jittered lattice above a 12 mm x 12 mm box, all at once.
rng = np.random.default_rng(42)
k = np.arange(600)
positions = np.column_stack([-4.5e-3 + 1.3e-3 * (k % 8), -4.5e-3 + 1.3e-3 * (k // 8 % 8), 1e-3 + 1.3e-3 * (k // 64)])
positions += rng.uniform(0, 5e-5, positions.shape)
world.add_balls(positions, rng.uniform(0.4e-3, 0.6e-3, 600), 2650.0)  # m, m, kg/m^3 (quartz)

# An open box of facet walls; outward normals point away from the sand.
h = 6e-3
world.add_wall("floor", libdem.make_rectangle([0, 0, 0], [h, 0, 0], [0, h, 0]), [0, 0, -1])
for n in ([1, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0]):
    n = np.array(n, dtype=float)
    along = np.cross(n, [0, 0, 1]) * h
    world.add_wall("side", libdem.make_rectangle(n * h + [0, 0, 8e-3], along, [0, 0, 8e-3]), n)

sand = libdem.RollingLinearParams.deformable(5e7, 1.0, 0.5, 0.2)  # E* (Pa), kn/ks, mu, mu_r
world.set_contact_model(libdem.ContactKind.BALL_BALL, sand, "ball-ball")
world.set_contact_model(libdem.ContactKind.BALL_FACET, sand, "ball-facet")

steps = int(sys.argv[1]) if len(sys.argv) > 1 else 2000
print(f"{'step':>8} {'time [s]':>10} {'kinetic [J]':>12} {'contacts':>8} {'top [mm]':>8}")
for line in range(21):
    top = world.positions[:, 2].max() * 1e3 if line else float("nan")
    print(f"{world.step_count:8d} {world.time:10.5f} {world.kinetic_energy():12.4e} "
          f"{world.contact_count(libdem.ContactKind.BALL_BALL):8d} {top:8.2f}")
    world.step(steps)
