"""The history log and the parts that add its columns, from Python: columns by name, the file as
written, and the uniformity probe on displacement fields whose measures are known exactly."""

import numpy as np
import pytest

import libdem


def with_laws(world):
    for kind in (libdem.ContactKind.BALL_BALL, libdem.ContactKind.BALL_FACET, libdem.ContactKind.BALL_PEBBLE):
        world.set_contact_model(kind, libdem.RollingLinearParams.deformable(1e7, 1.0, 0.5, 0.1), "law")
    return world


def small_cell(world, height=0.01):
    spec = libdem.ShearCellSpec()
    spec.diameter, spec.height, spec.pebble_diameter, spec.ring_gap = 0.02, height, 1.4e-3, 7e-5
    return libdem.build_shear_cell(world, spec)


def test_history_log_writes_the_columns_in_the_order_they_were_added(tmp_path):
    settings = libdem.WorldSettings()
    settings.time_step = 1e-6  # s
    world = libdem.World(settings)
    log = libdem.HistoryLog(tmp_path / "history.csv")
    log.add("time", lambda: world.time)
    log.add(["a", "b"], lambda: [world.step_count, 2.0 * world.step_count])
    calls = []
    log.before_row(lambda: calls.append(world.step_count))
    for _ in range(3):
        world.step(5)
        log.record()
    assert log.columns == ["time", "a", "b"] and log.rows == 3 and calls == [5, 10, 15]
    written = np.genfromtxt(tmp_path / "history.csv", delimiter=",", names=True)
    assert list(written.dtype.names) == ["time", "a", "b"]
    table = log.table()
    for name in log.columns:
        np.testing.assert_array_equal(written[name], table[name])
    np.testing.assert_array_equal(table["b"], [10.0, 20.0, 30.0])
    assert log.last("a") == 15.0
    with pytest.raises(ValueError, match="c"):
        log.add("c", lambda: 0.0)  # after the first row


def test_history_log_names_a_group_that_gives_the_wrong_number_of_values(tmp_path):
    log = libdem.HistoryLog(tmp_path / "history.csv")
    log.add(["first_of_two", "second_of_two"], lambda: [1.0])
    with pytest.raises(ValueError, match="first_of_two"):
        log.record()
    with pytest.raises(ValueError, match="first_of_two"):
        log.add("first_of_two", lambda: 0.0)  # a name already taken


def balls_in(world, cell, count, rng_seed):
    radii = np.full(count, 0.4e-3)
    centres = libdem.place_without_overlap(libdem.Cylinder(cell.radius - 1e-3, cell.built_height), radii, libdem.Random(rng_seed))
    for x, r in zip(centres, radii):
        world.add_ball(x, r, 2650.0)


def shift_balls(world, shift_of_height):
    """Moves every ball (not the pebbles) along x by shift_of_height(z)."""
    x = np.array(world.positions)
    free = np.array(world.clump_of) < 0
    x[free, 0] += shift_of_height(x[free, 2])
    world.set_positions(x)


def move_bottom_plate(world, cell, dx):
    """Moves the bottom plate by about dx along x in one step; returns the displacement it made."""
    plate = world.wall(cell.bottom)
    before = plate.displacement[0]
    plate.velocity = [dx / world.time_step, 0.0, 0.0]
    world.step(1)
    plate.velocity = [0.0, 0.0, 0.0]
    return plate.displacement[0] - before


@pytest.mark.parametrize("banded", [False, True])
def test_uniformity_probe_measures_a_uniform_and_a_banded_field(tmp_path, banded):
    settings = libdem.WorldSettings()
    settings.time_step = 1e-6  # s: one step moves the plate, the balls have no velocity
    world = with_laws(libdem.World(settings))
    cell = small_cell(world)
    balls_in(world, cell, 300, 5)
    log = libdem.HistoryLog(tmp_path / "history.csv")
    probe = libdem.UniformityProbe(world, cell, 6)
    probe.add_columns(log, lambda: np.array([1.0, 0.0, 0.0]))
    libdem.add_ring_columns(log, world, cell)
    log.record()  # starts the first interval: no profile yet
    assert np.isnan(log.last("profile_r2"))

    height = cell.plate_gap(world)
    u = move_bottom_plate(world, cell, 1e-3)
    assert u == pytest.approx(1e-3, rel=1e-9)
    if banded:  # the lower two thirds move with the bottom plate, the top third shears alone
        shift_balls(world, lambda z: u * np.clip(3.0 * (1.0 - z / height), 0.0, 1.0))
    else:  # uniform simple shear: u = U (1 - z / H)
        shift_balls(world, lambda z: u * (1.0 - z / height))
    log.record()

    strains = [log.last("strain_" + third + "_third") for third in ("bottom", "middle", "top")]
    assert log.last("bottom_dx") == u and log.last("top_dx") == 0.0
    if banded:
        # Bins of H/6: the bottom four bins are flat (strain 0), the top two carry 3 U / H; the
        # top third's slope is exact. R^2 is that of the bin means against the plates' line,
        # computed here from the balls' heights (negative: a block fits that line worse than a constant).
        assert strains[0] == pytest.approx(0.0, abs=1e-9) and strains[1] == pytest.approx(0.0, abs=1e-9)
        assert strains[2] == pytest.approx(3 * u / height, rel=1e-6)
        z = np.array(world.positions)[np.array(world.clump_of) < 0, 2]
        bin_of = np.minimum((z / height * 6).astype(int), 5)
        z_mean = np.array([z[bin_of == b].mean() for b in range(6)])
        u_mean = u * np.clip(3.0 * (1.0 - z_mean / height), 0.0, 1.0)  # linear within a bin
        residual = np.sum((u_mean - u * (1 - z_mean / height)) ** 2)
        expected_r2 = 1 - residual / np.sum((u_mean - u_mean.mean()) ** 2)
        assert expected_r2 < 0 and log.last("profile_r2") == pytest.approx(expected_r2, rel=1e-6)
    else:
        assert log.last("profile_r2") == pytest.approx(1.0, abs=1e-9)
        assert strains == pytest.approx([u / height] * 3, rel=1e-6)
        assert log.last("top_bottom_strain_ratio") == pytest.approx(1.0, rel=1e-6)
    assert libdem.specimen_porosity(world, cell) == pytest.approx(
        1 - 300 * 4 / 3 * np.pi * 0.4e-3**3 / (cell.area * height), rel=1e-12)
    assert log.columns[-2:] == ["ring_%d_dx" % cell.ring_count, "ring_%d_dy" % cell.ring_count]
    assert log.last("ring_1_dx") == 0.0  # the rings are held


def test_cyclic_paths_from_python():
    circle = libdem.CyclicPath(libdem.CyclicShape.CIRCLE, 0.0)
    assert np.linalg.norm(circle.at(1.3)) == pytest.approx(1.0, rel=1e-12)  # past the ramp: |value| = a
    sine = libdem.CyclicPath(libdem.CyclicShape.SINE, 90.0)
    assert sine.at(0.25) == pytest.approx([0.0, 1.0, 0.0], abs=1e-12)
    assert sine.length_cycles() == float("inf") and not sine.absolute
    with pytest.raises(ValueError, match="cyclic path minor_ratio"):
        libdem.CyclicPath(libdem.CyclicShape.ELLIPSE, 0.0, -1.0)
