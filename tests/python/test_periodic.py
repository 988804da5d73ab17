"""The periodic cell through Python: a face-centred cubic lattice in its cell has twelve contacts a
ball and an isotropic stress, a servo brings it to a target stress, and the strain of the cell
comes back from its matrix."""

import math

import numpy as np
import pytest

import libdem


def lattice(cells=3, radius=0.5e-3, overlap=0.01e-3):
    """A face-centred cubic lattice of equal balls, every neighbour pair overlapping, in its cell."""
    a = math.sqrt(2.0) * (2 * radius - overlap)
    basis = np.array([[0, 0, 0], [0.5, 0.5, 0], [0.5, 0, 0.5], [0, 0.5, 0.5]])
    corners = np.array([[i, j, k] for i in range(cells) for j in range(cells) for k in range(cells)], dtype=float)
    positions = ((corners[:, None, :] + basis[None, :, :]).reshape(-1, 3) + 0.25) * a
    world = libdem.World(libdem.WorldSettings())
    world.add_balls(positions, np.full(len(positions), radius), 2650.0)
    world.set_periodic_cell(libdem.PeriodicCell.box([0, 0, 0], [cells * a] * 3))
    world.set_contact_model(libdem.ContactKind.BALL_BALL, libdem.LinearParams.constant(4e4, 4e4, 0.5), "ball-ball")
    return world


def test_a_lattice_in_its_cell_has_twelve_contacts_a_ball_and_an_isotropic_stress():
    world = lattice()
    world.step(1)
    packing = libdem.cell_packing(world)
    assert packing["balls"] == 108 and packing["coordination_number"] == 12.0
    stress = libdem.cell_stress(world)["stress"]
    assert stress[0, 0] < 0  # tension positive: the springs push
    assert np.allclose(stress, stress[0, 0] * np.eye(3), rtol=0, atol=1e-9 * abs(stress[0, 0]))
    assert world.periodic_cell.volume == pytest.approx(libdem.cell_stress(world)["volume"])


def test_a_servo_brings_the_cell_to_a_stress_and_the_strain_comes_back_from_the_matrix():
    world = lattice()
    world.step(1)
    world.update_time_step()
    start = world.periodic_cell.matrix
    target = -1.5 * np.trace(libdem.cell_stress(world)["stress"]) / 3
    servo = libdem.add_cell_servo(world, stress={"xx": target, "yy": target, "zz": target}, max_rate=2.0)
    assert world.run_until(lambda w: servo.settled, 100, 50_000)
    assert -np.diag(servo.stress) == pytest.approx([target] * 3, rel=0.01)
    strain = libdem.cell_strain(start, world.periodic_cell.matrix)
    assert strain["volumetric_strain"] == pytest.approx(math.log(world.periodic_cell.volume / np.linalg.det(start)))
    assert strain["volumetric_strain"] < 0  # compressed
    with pytest.raises(ValueError, match="one of xx, yy, zz, yz, xz, xy"):
        servo.set_rate("zx", 0.0)


def test_an_element_test_runs_a_drained_triaxial_holding_sigma_3_and_resumes(tmp_path):
    keys = {"element": {"test": "triaxial-drained", "balls": 200, "target_strain": 0.01, "every_strain": 0.001},
            "output.restart_every_steps": 10, "engine.threads": 1}
    test = libdem.ElementTest(keys, out=tmp_path / "tx", preset="4D", progress=False)
    test.run()
    test.write_summary()
    h = test.history()
    shearing = h["stage"] == 1
    assert h["axial_strain"][-1] >= 0.01
    # Drained: the servo holds the lateral stresses at the confining stress (1 %, the protocol's bound).
    for column in ("cell_stress_xx", "cell_stress_yy"):
        assert h[column][shearing] == pytest.approx(1e5, rel=0.01)
    assert h["deviator_stress"][-1] == pytest.approx(h["cell_stress_zz"][-1] - h["cell_stress_xx"][-1], rel=0.02)
    assert (tmp_path / "tx" / "summary.json").exists()
    # Resumed from its restart file (keys checked), the run ends where the whole one did.
    again = libdem.ElementTest(keys, out=tmp_path / "tx2", preset="4D", progress=False)
    again.load_restart(tmp_path / "tx" / "consolidated.restart")
    again.run()
    assert again.history()["deviator_stress"][-1] == h["deviator_stress"][-1]
    with pytest.raises(ValueError, match="element.test"):
        libdem.ElementTest({"element.test": "uniaxial"}, out=tmp_path / "bad")
