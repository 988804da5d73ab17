"""Bonds through Python: a bond pulled at a held speed carries kn A delta in tension until the stress at
its edge passes its tensile strength, then breaks and keeps that load; cement() bonds the close pairs
only; a bad material is refused by name."""

import math

import numpy as np
import pytest

import libdem

RADIUS = 1e-3  # m
GAP = 1e-5     # m: the balls never touch, only the bond acts


def pulled_pair(material, speed=1e-3, dt=1e-6):
    settings = libdem.WorldSettings()
    settings.local_damping = 0.0
    world = libdem.World(settings)
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(1e4, 1e4, 0.0), "ball-ball")
    a = world.add_ball([0.0, 0.0, 0.0], RADIUS, 2650.0, fixed=libdem.DOF_ALL)
    b = world.add_ball([2 * RADIUS + GAP, 0.0, 0.0], RADIUS, 2650.0, velocity=[speed, 0.0, 0.0], fixed=libdem.DOF_ALL)
    assert world.add_bond(a, b, material) == 0
    world.time_step = dt
    return world


def test_a_bond_in_tension_carries_kn_area_elongation_and_breaks_at_its_strength():
    # each step stretches the bond by speed dt = 1 nm: sigma = kn x elongation rises 100 Pa a step
    kn, strength, speed, dt = 1e11, 2050.0, 1e-3, 1e-6
    material = libdem.BondMaterial(normal_stiffness=kn, shear_stiffness=kn, tensile_strength=strength, cohesion=1e9)
    world = pulled_pair(material, speed, dt)
    area = math.pi * RADIUS**2  # radius_multiplier 1: the disc of the smaller ball
    world.step(10)
    bonds = world.bonds()
    assert list(bonds["first"]) == [0] and list(bonds["second"]) == [1] and list(bonds["status"]) == [0]
    assert bonds["radius"][0] == RADIUS
    # tension positive, 10 steps of speed dt elongation; the sum of 10 increments: 1e-12 relative
    assert bonds["normal_force"][0] == pytest.approx(kn * area * 10 * speed * dt, rel=1e-12)
    assert np.abs(bonds["shear_force"]).max() == 0.0
    assert bonds["strain_energy"][0] == pytest.approx(bonds["normal_force"][0] ** 2 / (2 * kn * area), rel=1e-12)
    # sigma = F_n / A = 100 n Pa passes 2050 Pa on step 21: broken on that step, the first past it
    broke = None
    for n in range(11, 40):
        world.step()
        if world.bonds()["status"][0] != 0:
            broke = n
            break
    assert broke == 21
    bonds = world.bonds()
    assert bonds["status"][0] == 1  # broken in tension
    assert world.bond_energy_released == pytest.approx(bonds["strain_energy"][0], rel=1e-15)
    assert world.bond_energy_released > 0.0


def test_cement_bonds_the_close_pairs_only():
    world = libdem.World()
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(1e4, 1e4, 0.3), "ball-ball")
    # 0-1 touching, 1-2 a gap of 2 % of R, 2-3 a gap of 20 % of R
    x = [0.0, 2 * RADIUS, 4.02 * RADIUS, 6.22 * RADIUS]
    for xi in x:
        world.add_ball([xi, 0.0, 0.0], RADIUS, 2650.0)
    material = libdem.BondMaterial(normal_stiffness=1e11, shear_stiffness=1e11, tensile_strength=1e6, cohesion=1e6,
                                   tensile_strength_std=2e5, seed=7)
    assert libdem.cement(world, material, gap_ratio=0.05) == 2
    bonds = world.bonds()
    assert sorted(zip(bonds["first"], bonds["second"])) == [(0, 1), (1, 2)]
    assert np.all(bonds["status"] == 0) and np.all(bonds["normal_force"] == 0.0)
    # strengths drawn per bond: different bonds, different draws, the same on a second cementation
    assert bonds["tensile_strength"][0] != bonds["tensile_strength"][1]
    again = libdem.World()
    again.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(1e4, 1e4, 0.3), "ball-ball")
    for xi in x:
        again.add_ball([xi, 0.0, 0.0], RADIUS, 2650.0)
    libdem.cement(again, material, gap_ratio=0.05)
    assert np.array_equal(again.bonds()["tensile_strength"], bonds["tensile_strength"])
    assert libdem.cement(world, material, gap_ratio=0.05) == 0  # pairs already bonded are left as they are


def test_bad_bonds_are_refused_by_name():
    with pytest.raises(ValueError, match="radius_multiplier"):
        libdem.BondMaterial(radius_multiplier=1.5, normal_stiffness=1e11, shear_stiffness=1e11, tensile_strength=1e6,
                            cohesion=1e6)
    with pytest.raises(ValueError, match="normal_stiffness"):
        libdem.BondMaterial(normal_stiffness=0.0, shear_stiffness=1e11, tensile_strength=1e6, cohesion=1e6)
    material = libdem.BondMaterial(normal_stiffness=1e11, shear_stiffness=1e11, tensile_strength=1e6, cohesion=1e6)
    world = pulled_pair(material)
    with pytest.raises(ValueError, match="two different balls"):
        world.add_bond(0, 0, material)
    with pytest.raises(ValueError, match="bond ball id"):
        world.add_bond(0, 5, material)
