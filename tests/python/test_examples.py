"""The Python examples run as a user runs them: the pour settles into the box, and the oedometer's
K0 is larger on unloading than on loading at the same stress (an overconsolidated packing keeps
locked-in lateral stress)."""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "python"


def run(script, *args, cwd=None):
    return subprocess.run([sys.executable, str(EXAMPLES / script), *map(str, args)], check=True, capture_output=True,
                          text=True, env=dict(os.environ), cwd=cwd).stdout


def test_pour_settles_into_the_box():
    lines = run("pour.py", 1000).splitlines()[1:]
    top = [float(line.split()[4]) for line in lines[1:]]
    kinetic = [float(line.split()[2]) for line in lines]
    # mm: the lattice's top row starts at 1 + 1.3 x 9 mm + a radius (<= 13.4 mm); the balls fall
    # into the box, whose floor is at 0, and stay there.
    assert top[0] < 13.4 and all(t > 0.4 for t in top)
    assert all(t < top[0] + 1e-9 for t in top)  # the pile only comes down
    assert kinetic[-1] < max(kinetic)


def test_oedometer_unloading_k0_is_above_loading(tmp_path):
    run("oedometer.py", tmp_path / "oedometer.csv", cwd=tmp_path)
    rows = np.loadtxt(tmp_path / "oedometer.csv", delimiter=",", skiprows=1)
    sigma_v, k0 = rows[:, 0], rows[:, 2]
    assert np.allclose(sigma_v, [50e3, 100e3, 200e3, 100e3, 50e3], rtol=0.02)  # the servo's tolerance
    assert k0[3] > k0[1] and k0[4] > k0[0]  # unloading above loading at 100 and 50 kPa
    assert np.all((k0 > 0.2) & (k0 < 1.5))


def test_k0_then_constant_volume_shear_holds_the_height_and_follows_jaky(tmp_path):
    """examples/k0_constant_volume.cpp, the protocol built from the lab toolkit: the held plate
    keeps the height through the constant-volume shear, and the K0 of the last load step agrees
    with Jaky's 1 - sin(phi) for the friction angle the same specimen mobilises in simple shear
    (tau/sigma_v = sin(phi) at the peak, Davis's reading of simple shear); Jaky's formula fits
    sands to about 0.1, the bound used here."""
    program = Path(os.environ.get("LIBDEM_BUILD_DIR", "build")) / "examples" / "k0_constant_volume"
    out = subprocess.run([str(program), str(tmp_path / "cv.csv"), "0.12"], check=True, capture_output=True,
                         text=True).stdout
    load_steps = [line.split() for line in out.splitlines() if line.strip().endswith(("yes", "no"))]
    assert [row[-1] for row in load_steps] == ["yes"] * 3  # every load step settled on its target
    sigma_v = np.array([float(row[0]) for row in load_steps]) * 1e3
    assert np.allclose(sigma_v, [50e3, 100e3, 200e3], rtol=0.01)  # the servo's settle tolerance
    k0 = float(load_steps[-1][3])

    rows = np.loadtxt(tmp_path / "cv.csv", delimiter=",", skiprows=1)
    strain, ratio, height = rows[:, 0], rows[:, 3], rows[:, 4]
    assert strain[-1] >= 0.12
    assert np.all(np.abs(height - height[0]) <= 1e-12 * height[0])
    assert abs(k0 - (1 - ratio.max())) < 0.1


def test_the_python_toolkit_protocol_writes_the_numbers_of_its_cpp_twin(tmp_path):
    """examples/python/k0_constant_volume.py composes the same toolkit parts in the same order as
    examples/k0_constant_volume.cpp, with the same seed: every value of its table is the same
    double (the bindings add no arithmetic; a Python controller only calls the C++ parts)."""
    program = Path(os.environ.get("LIBDEM_BUILD_DIR", "build")) / "examples" / "k0_constant_volume"
    subprocess.run([str(program), str(tmp_path / "cpp.csv"), "0.03"], check=True, capture_output=True)
    run("k0_constant_volume.py", tmp_path / "py.csv", "0.03")
    cpp = np.loadtxt(tmp_path / "cpp.csv", delimiter=",", skiprows=1)
    python = np.loadtxt(tmp_path / "py.csv", delimiter=",", skiprows=1)
    assert cpp.shape == python.shape and cpp.shape[0] >= 6
    assert np.array_equal(cpp, python)

