"""The lab protocols through Python: the simple-shear run is the C++ app's, byte for byte; the
cyclic test runs on the consolidated specimen and reports its cycles; the toolkit's parts place
balls without overlap, move the plates of a shear leg and refuse bad input with the library's
message."""

import subprocess

import numpy as np
import pytest

import libdem
from conftest import REDUCED


def test_simple_shear_from_python_equals_the_app(tmp_path, apps):
    config = dict(REDUCED, shear={"target_strain": 0.02}, output={"fabric_strains": [0.0], "snapshot_strains": [0.0]})
    test = libdem.SimpleShear(config, out=tmp_path / "python", preset="4D", quiet=True)
    test.open_outputs()
    test.run()
    test.write_summary()
    subprocess.run([str(apps / "dem-simple-shear"), "--preset", "4D", "--out", str(tmp_path / "app"),
                    "--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012", "--set", "engine.threads=1",
                    "--set", "shear.target_strain=0.02", "--set", "output.fabric_strains=0",
                    "--set", "output.snapshot_strains=0"], check=True, stdout=subprocess.DEVNULL)
    assert (tmp_path / "python" / "history.csv").read_bytes() == (tmp_path / "app" / "history.csv").read_bytes()
    history = test.history()
    assert history["shear_strain"][-1] == pytest.approx(0.02, abs=2e-4)
    assert test.stage == 4


def test_cyclic_shear_from_python(tmp_path):
    specimen = libdem.SimpleShear(REDUCED, out=tmp_path, preset="4D", quiet=True)
    specimen.open_outputs()
    specimen.generate()
    specimen.consolidate()
    cyclic = libdem.CyclicShear(specimen, {"csr": 0.1, "max_cycles": 2, "path": "circle"}, quiet=True)
    cyclic.run()
    cyclic.write_summary()
    outcome = cyclic.outcome
    assert outcome["stop"] == "cycles" and outcome["cycles"] == 2.0
    cycles = cyclic.cycles()
    assert list(cycles["cycle"]) == [1.0, 2.0]
    history = cyclic.history()
    phase = history["phase"]
    assert np.count_nonzero(phase == 1) == 2 * 40 + 1  # 40 rows a cycle and the start
    with pytest.raises(ValueError, match="cyclic.path"):
        libdem.CyclicShear(specimen, {"path": "square"})


def test_toolkit_places_balls_clear_of_each_other_and_refuses_a_full_cavity():
    radii = np.random.default_rng(1).uniform(0.3e-3, 0.5e-3, 300)
    x = libdem.place_without_overlap(libdem.Cylinder(6e-3, 5e-3), radii, libdem.Random(3))
    assert x.shape == (300, 3)
    assert np.all(np.hypot(x[:, 0], x[:, 1]) <= 6e-3 - radii) and np.all(x[:, 2] >= radii)
    gaps = np.linalg.norm(x[:, None] - x[None], axis=2) - (radii[:, None] + radii[None])
    assert np.all(gaps[~np.eye(300, dtype=bool)] >= 0)
    with pytest.raises(ValueError, match="no room for ball"):
        libdem.place_without_overlap(libdem.Cylinder(3e-3, 4e-3), np.full(40, 1e-3), libdem.Random(1))


def test_toolkit_shear_leg_moves_the_plates_by_speed_times_time():
    settings = libdem.WorldSettings()
    settings.time_step = 1e-5  # s
    world = libdem.World(settings)
    spec = libdem.ShearCellSpec()
    spec.diameter, spec.height, spec.pebble_diameter, spec.ring_gap = 0.012, 0.006, 1.4e-3, 7e-5
    cell = libdem.build_shear_cell(world, spec)
    servo = libdem.ServoWall(cell.top, libdem.ServoSettings(1e3, 0.01))
    path = libdem.ShearPath(world, cell, 0.006)
    libdem.start_shear_leg(world, cell, servo, libdem.ShearLegMotion(90.0, 0.01, libdem.ShearMode.CONSTANT_VOLUME))
    world.step(100)
    assert path.advance(world, cell) == pytest.approx(100 * 0.01 * 1e-5 / 0.006, rel=1e-12)
    assert libdem.plate_offset(world, cell) == pytest.approx([0, 100 * 0.01 * 1e-5, 0], abs=1e-15)


def test_toolkit_horizontal_drive_puts_the_strain_on_the_path_at_every_step():
    settings = libdem.WorldSettings()
    settings.time_step = 1e-5  # s
    world = libdem.World(settings)
    spec = libdem.ShearCellSpec()
    spec.diameter, spec.height, spec.pebble_diameter, spec.ring_gap = 0.012, 0.006, 1.4e-3, 7e-5
    cell = libdem.build_shear_cell(world, spec)
    drive = libdem.HorizontalDrive(libdem.HorizontalDriveSettings(cell.top, cell.bottom, cell.area, 0.006, max_speed=0.1))
    world.add_controller(lambda w: drive(w))
    path, amplitude, steps_per_cycle = libdem.CyclicPath(libdem.CyclicShape.FIGURE8, 30.0), 0.01, 200.0
    drive.follow_strain(lambda n: amplitude * path.at(n), world.step_count, steps_per_cycle)
    for _ in range(7):
        world.step(37)
        n = drive.cycles_at(world.step_count)
        assert libdem.plate_offset(world, cell) / 0.006 == pytest.approx(amplitude * path.at(n), abs=1e-15)
    drive.move_bottom(np.array([0.0, 0.02, 0.0]))  # then monotonic: 0.02 m/s along +y
    before = libdem.plate_offset(world, cell)
    world.step(100)
    assert libdem.plate_offset(world, cell) - before == pytest.approx([0.0, 100 * 0.02 * 1e-5, 0.0], abs=1e-15)
    assert drive.work == 0.0  # no balls: no force on the top plate
    with pytest.raises(ValueError, match="horizontal drive max_speed"):
        libdem.HorizontalDrive(libdem.HorizontalDriveSettings(cell.top, cell.bottom, cell.area, 0.006, max_speed=0.0))
