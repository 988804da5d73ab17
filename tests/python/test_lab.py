"""The lab protocols through Python: the simple-shear run is the C++ app's, byte for byte; the
cyclic test runs on the consolidated specimen and reports its cycles."""

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
