"""The engine through Python: a head-on impact against its analytic duration, views that follow the
state, a Python controller driving a wall, callbacks and errors that carry the library's message."""

import math

import numpy as np
import pytest

import libdem


def two_balls(kn, radius=1e-3, density=2650.0, speed=0.05):
    settings = libdem.WorldSettings()
    settings.local_damping = 0.0
    world = libdem.World(settings)
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(kn, kn, 0.0), "ball-ball")
    world.add_ball([0.0, 0.0, 0.0], radius, density, velocity=[speed, 0.0, 0.0])
    world.add_ball([2 * radius + 1e-6, 0.0, 0.0], radius, density, velocity=[-speed, 0.0, 0.0])
    return world


def test_head_on_impact_lasts_pi_sqrt_meff_over_kn():
    # Linear spring, no damping: contact lasts half a period of m_eff on kn, pi sqrt(m_eff / kn),
    # and the balls leave with the speeds they came with.
    kn, radius, density = 1e4, 1e-3, 2650.0
    world = two_balls(kn, radius, density)
    mass = density * 4.0 / 3.0 * math.pi * radius**3
    expected = math.pi * math.sqrt(0.5 * mass / kn)
    world.time_step = expected / 400  # 400 steps of contact: the duration is resolved to 1/200
    touching = []
    world.add_callback(1, lambda w: touching.append(w.contact_count(libdem.ContactKind.BALL_BALL) > 0))
    world.step(1200)
    steps = sum(touching)
    assert touching[0] is False and touching[-1] is False
    assert steps * world.time_step == pytest.approx(expected, rel=2 / 400)
    speeds = np.linalg.norm(world.velocities, axis=1)
    assert speeds == pytest.approx([0.05, 0.05], rel=1e-3)


def test_views_follow_the_state_after_each_step_and_are_read_only():
    settings = libdem.WorldSettings()
    settings.local_damping = 0.0
    world = libdem.World(settings)
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(1e4, 1e4, 0.0), "ball-ball")
    ids = world.add_balls(np.array([[0.0, 0, 0], [0.01, 0, 0], [0.0, 0.01, 0]]), np.array([1e-3, 1e-3, 1.5e-3]), 2650.0)
    assert list(ids) == [0, 1, 2]
    velocity = np.array([[0.1, 0, 0], [0, -0.2, 0], [0, 0, 0.3]])
    world.set_velocities(velocity)
    world.time_step = 1e-5
    start = world.positions.copy()
    for n in range(1, 6):
        world.step()
        # No contact, no damping, no gravity: x = x0 + v t, row by row in storage order.
        order = [world.index_of(i) for i in ids]
        assert np.allclose(world.positions[order], start + velocity * n * 1e-5, rtol=0, atol=1e-15)
        assert np.array_equal(world.ids[order], ids)
    assert world.radii[world.index_of(2)] == 1.5e-3
    with pytest.raises(ValueError):
        world.positions[0, 0] = 1.0


def test_a_python_controller_moves_a_wall():
    world = libdem.World()
    world.set_contact_model(libdem.ContactKind.BALL_FACET, libdem.LinearParams.constant(1e4, 1e4, 0.0), "ball-facet")
    world.add_ball([0.0, 0.0, 0.01], 1e-3, 2650.0)
    wall = world.add_wall("floor", libdem.make_disc([0, 0, 0], 0.02, [0, 0, -1]), [0, 0, -1])
    world.time_step = 1e-5

    def lower(w):
        w.wall(0).velocity = [0.0, 0.0, -0.01] if w.step_count >= 4 else [0.0, 0.0, 0.0]

    world.add_controller(lower)
    world.step(10)
    # Six steps (4..9) at -0.01 m/s.
    assert wall.displacement == pytest.approx([0, 0, -0.01 * 6 * 1e-5], abs=1e-18)


def test_a_ball_settles_on_an_analytic_plane_with_its_weight_on_it():
    world = libdem.World()
    world.set_contact_model(libdem.ContactKind.BALL_FACET, libdem.LinearParams.constant(1e4, 1e4, 0.5), "ball-facet")
    world.set_gravity([0.0, 0.0, -9.81])
    world.add_ball([0.0, 0.0, 1.0e-3 + 1e-6], 1e-3, 2650.0)
    floor = world.add_plane_wall("floor", [0.0, 0.0, 0.0], [0.0, 0.0, -1.0], area=1e-4)
    world.time_step = 1e-5
    world.step(4000)  # local damping 0.7 settles the bounce (period 2e-4 s) in well under 0.04 s
    weight = 2650.0 * 4.0 / 3.0 * np.pi * 1e-9 * 9.81
    assert floor.contact_count == 1
    # Equilibrium: the floor carries the weight; what is left is the damped oscillation's round-off.
    assert floor.force == pytest.approx([0.0, 0.0, -weight], rel=1e-9, abs=1e-15)
    assert floor.normal_stress == pytest.approx(weight / 1e-4, rel=1e-9)
    with pytest.raises(ValueError, match="area"):
        world.add_plane_wall("bad", [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], area=0.0)


def test_a_damping_frame_that_outruns_a_ball_brakes_it_by_one_plus_alpha():
    # docs/model.md 3.1: gravity opposes the ball's velocity relative to a frame falling at 1 m/s,
    # so local damping 0.7 gives (1 + 0.7) g from the first step; in the fixed frame (1 - 0.7) g.
    settings = libdem.WorldSettings()
    settings.gravity, settings.time_step = [0.0, 0.0, -9.81], 1e-5
    world = libdem.World(settings)
    world.add_ball([0.0, 0.0, 0.0], 1e-3, 2650.0)
    frame = libdem.DampingFrame()
    frame.velocity = [0.0, 0.0, -1.0]
    world.set_damping_frame(frame)
    assert world.damping_frame.velocity_at([0.0, 0.0, 0.5]) == pytest.approx([0.0, 0.0, -1.0])
    world.step(1000)
    assert world.velocities[0, 2] == pytest.approx(-1.7 * 9.81 * 1000 * 1e-5, rel=1e-12)
    world.set_damping_frame(libdem.DampingFrame())
    v0 = world.velocities[0, 2]
    world.step(1000)
    assert (world.velocities[0, 2] - v0) / 1e-2 == pytest.approx(-0.3 * 9.81, rel=1e-12)


def test_run_until_and_measurement_sphere():
    world = two_balls(1e4)
    world.time_step = 1e-6
    assert world.run_until(lambda w: w.contact_count(libdem.ContactKind.BALL_BALL) > 0, 1, 100000)
    m = world.measure([1e-3, 0.0, 0.0], 5e-3)
    assert m["balls"] == 2 and m["contacts"] == 1
    assert m["stress"].shape == (3, 3)
    c = world.contacts()
    assert list(c["kind"]) == [int(libdem.ContactKind.BALL_BALL)]
    assert c["normal"][0] == pytest.approx([1, 0, 0])


def test_errors_carry_the_library_message():
    world = libdem.World()
    with pytest.raises(ValueError, match="radius = -1"):
        world.add_ball([0, 0, 0], -1.0, 2650.0)
    # A time step far above the stable one: the overlap grows past the limit.
    bad = two_balls(1e6, speed=1.0)
    bad.time_step = 1e-3
    with pytest.raises(libdem.InstabilityError, match="ball id"):
        bad.step(20)

    def fails(w):
        raise KeyError("from the controller")

    world.add_ball([0, 0, 0], 1e-3, 2650.0)
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(1e4, 1e4, 0.0), "ball-ball")
    world.add_controller(fails)
    with pytest.raises(KeyError, match="from the controller"):
        world.step()


def test_save_and_load_state_continue_bit_for_bit(tmp_path):
    a = two_balls(1e4)
    a.time_step = 1e-6
    a.step(300)
    a.save_state(tmp_path / "state.bin")
    a.step(300)
    b = two_balls(1e4)
    b.load_state(tmp_path / "state.bin")
    b.step(300)
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.velocities, b.velocities)


def test_each_law_is_set_as_given():
    # A RollingLinearParams is also a LinearParams: the rolling law must not be taken for the plain one.
    world = libdem.World()
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.RollingLinearParams.deformable(1e7, 1.0, 0.5, 0.2))
    world.set_contact_model(libdem.ContactKind.BALL_FACET, libdem.LinearParams.deformable(1e7, 1.0, 0.5))
    assert world.contact_law(libdem.ContactKind.BALL_BALL) == "rolling-linear"
    assert world.contact_law(libdem.ContactKind.BALL_FACET) == "linear"
    assert world.contact_law(libdem.ContactKind.BALL_PEBBLE) == ""


def test_servo_plate_on_a_ball_and_a_ring_stack():
    world = libdem.World()
    law = libdem.LinearParams.constant(1e5, 1e5, 0.3)
    world.set_contact_model(libdem.ContactKind.BALL_FACET, law)
    world.set_contact_model(libdem.ContactKind.BALL_BALL, law)
    world.set_contact_model(libdem.ContactKind.BALL_PEBBLE, law)
    world.add_ball([0, 0, 1e-3], 1e-3, 2650.0, fixed=libdem.DOF_ALL)
    world.add_wall("bottom", libdem.make_disc([0, 0, 0], 5e-3, [0, 0, -1]), [0, 0, -1])
    top = world.add_wall("top", libdem.make_disc([0, 0, 2.2e-3], 5e-3, [0, 0, 1]), [0, 0, 1], area=1e-4)
    servo = world.add_servo_wall(top.id, libdem.ServoSettings(target_stress=1e3, max_speed=0.01, settle_steps=200))
    assert world.run_until(lambda w: servo.settled, 100, 200000)
    # 1 kPa over 1e-4 m^2 is 0.1 N on the ball: an overlap of 0.1 / 1e5 m.
    assert top.normal_stress == pytest.approx(1e3, rel=0.01)
    assert 2.2e-3 + top.displacement[2] - 2e-3 == pytest.approx(-0.1 / 1e5, rel=0.02)
    spec = libdem.RingStackSpec()
    spec.inner_radius, spec.height, spec.ring_height, spec.pebble_radius = 5e-3, 4e-3, 1e-3, 0.5e-3
    rings = world.add_ring_stack(spec)
    assert len(rings) == 4  # 4 mm covered by rings 1 mm tall
    assert np.count_nonzero(world.clump_of >= 0) > 0


def test_a_controller_reads_contacts_only_with_every_step_records():
    # The head-on impact: the 1 um gap closes at 0.1 m/s in 50 steps of 0.2 us, and the contact
    # lasts pi sqrt(m_eff / kn) = 74 us, 370 steps: steps 100-120 are all in contact.
    world = two_balls(1e4)
    world.time_step = 2e-7
    world.step(100)
    counts = []
    world.add_controller(lambda w: counts.append(w.contact_count(libdem.ContactKind.BALL_BALL)))
    assert world.contact_records == libdem.ContactRecords.WHEN_READ
    with pytest.raises(RuntimeError, match="EveryStep"):
        world.step(10)  # its first step skips the records
    world.contact_records = libdem.ContactRecords.EVERY_STEP
    counts.clear()
    world.step(10)
    assert counts == [1] * 10


def test_contact_laws_by_keyword():
    """The registry's laws by keyword, as the apps' `<type>.law` key names them: listed with their
    parameters' units, set on a World by keyword (unknown laws and parameters refused by name), and
    the law a SimpleShear configuration names reaches its World."""
    laws = {law["keyword"]: law for law in libdem.contact_laws()}
    assert list(laws)[0] == "rrlinear" and "linear" in laws
    assert laws["rrlinear"]["parameters"]["effective_modulus"]["unit"] == "Pa"
    assert "rolling_friction" in laws["rrlinear"]["parameters"] and "rolling_friction" not in laws["linear"]["parameters"]
    world = libdem.World()
    world.set_contact_law(libdem.ContactKind.BALL_BALL, "linear", {"effective_modulus": 1e8, "friction": 0.3}, "ball_ball")
    assert world.contact_law(libdem.ContactKind.BALL_BALL) == "linear"
    world.set_contact_law(libdem.ContactKind.BALL_BALL, "rrlinear")
    assert world.contact_law(libdem.ContactKind.BALL_BALL) == "rolling-linear"
    with pytest.raises(ValueError, match="hertz.*rrlinear"):
        world.set_contact_law(libdem.ContactKind.BALL_BALL, "hertz")
    with pytest.raises(ValueError, match="ball_ball.rolling_friction.*linear"):
        world.set_contact_law(libdem.ContactKind.BALL_BALL, "linear", {"rolling_friction": 0.1}, "ball_ball")
    with pytest.raises(ValueError, match="ball_ball.friction"):
        world.set_contact_law(libdem.ContactKind.BALL_BALL, "linear", {"friction": -1.0}, "ball_ball")
    # Hertz-Mindlin with its material, and its damping model named as the apps' key takes it
    assert laws["hertz-mindlin"]["parameters"]["damping_model"]["choices"] == ["liggghts", "tsuji"]
    world.set_contact_law(libdem.ContactKind.BALL_BALL, "hertz-mindlin",
                          {"youngs_modulus": 7e10, "restitution": 0.7, "damping_model": "tsuji"}, "ball_ball")
    assert world.contact_law(libdem.ContactKind.BALL_BALL) == "hertz-mindlin"
    with pytest.raises(ValueError, match="ball_ball.damping_model = hooke.*liggghts, tsuji"):
        world.set_contact_law(libdem.ContactKind.BALL_BALL, "hertz-mindlin", {"damping_model": "hooke"}, "ball_ball")
    # and its rolling resistance model: LIGGGHTS's epsd2 spring, its constant directional torque, or none
    assert laws["hertz-mindlin"]["parameters"]["rolling"]["choices"] == ["epsd", "cdt", "none", "sds"]
    world.set_contact_law(libdem.ContactKind.BALL_BALL, "hertz-mindlin", {"rolling_friction": 0.1, "rolling": "cdt"},
                          "ball_ball")
    with pytest.raises(ValueError, match="ball_ball.rolling = bogus.*epsd, cdt, none"):
        world.set_contact_law(libdem.ContactKind.BALL_BALL, "hertz-mindlin", {"rolling": "bogus"}, "ball_ball")
