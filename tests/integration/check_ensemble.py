#!/usr/bin/python3
"""CTest ensemble_seeds: scripts/ensemble on two seeds of a reduced specimen (30 mm x 12 mm, 4D
balls, 1 % strain: seconds per seed).

Checked: each seed's run is in its own folder with its own specimen (the seeds differ); every
mean in ensemble.csv is the mean of the two seeds' values of that row and column, min <= mean <=
max, std is the sample standard deviation |a - b| / sqrt(2); ensemble.json's ball count is the
mean of the summaries'; a second call runs nothing again; scripts/plot draws the ensemble.

Usage: check_ensemble.py SOURCE_DIR DEM_ENSEMBLE
"""

import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

source, app = Path(sys.argv[1]), sys.argv[2]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def table(path):
    with open(path) as f:
        names = f.readline().strip().split(",")
        rows = np.array([[float(x) for x in line.split(",")] for line in f if line.strip()])
    return names, rows


with tempfile.TemporaryDirectory() as tmp:
    out = Path(tmp) / "ens"
    args = [sys.executable, str(source / "scripts" / "ensemble"), "--seeds", "1-2", "--jobs", "2", "--out", str(out),
            "--app", app, "--", "--preset", "4D", "--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012",
            "--set", "shear.target_strain=0.01", "--set", "output.fabric_strains=0", "--set", "output.snapshot_strains=0"]
    first = subprocess.run(args, capture_output=True, text=True)
    print(first.stdout, first.stderr)
    check(first.returncode == 0, "scripts/ensemble exits 0")
    names_a, a = table(out / "seed_1" / "history.csv")
    names_b, b = table(out / "seed_2" / "history.csv")
    names, e = table(out / "ensemble.csv")
    rows = min(len(a), len(b))
    check(len(e) == rows, f"ensemble.csv has the common rows ({len(e)} of {rows})")
    check(not np.array_equal(a[:rows], b[:rows]), "the two seeds made different specimens")
    worst = 0.0
    ordered = True
    for c, name in enumerate(names_a):
        pair = np.stack([a[:rows, c], b[:rows, names_b.index(name)]])
        both = np.all(np.isfinite(pair), axis=0)
        mean = e[:rows, names.index(name + "_mean")]
        low, high = e[:rows, names.index(name + "_min")], e[:rows, names.index(name + "_max")]
        std = e[:rows, names.index(name + "_std")]
        expected = pair.mean(axis=0)
        # Relative to the values' size: the spread of two nearly equal values is pure rounding.
        scale = np.maximum(np.abs(expected), 1e-300)
        worst = max(worst, float(np.max(np.abs(mean[both] - expected[both]) / scale[both], initial=0.0)))
        worst = max(worst, float(np.max(np.abs(std[both] - np.abs(pair[0] - pair[1])[both] / math.sqrt(2))
                                        / scale[both], initial=0.0)))
        ordered &= bool(np.all(low[both] <= mean[both]) and np.all(mean[both] <= high[both]))
    # Two doubles averaged by numpy: a few units in the last place.
    check(worst < 1e-12, f"means and standard deviations are those of the seeds (largest relative error {worst:.2e})")
    check(ordered, "min <= mean <= max in every row and column")
    stats = json.loads((out / "ensemble.json").read_text())["statistics"]
    balls = [json.loads((out / f"seed_{s}" / "summary.json").read_text())["balls"] for s in (1, 2)]
    check(stats["balls"]["mean"] == sum(balls) / 2, "ensemble.json: the mean ball count of the two summaries")
    again = subprocess.run(args, capture_output=True, text=True)
    check(again.returncode == 0 and again.stdout.count("done already") == 2, "a second call reuses both seeds")
    figures = Path(tmp) / "figures"
    plot = subprocess.run([sys.executable, str(source / "scripts" / "plot"), str(out), "--out", str(figures)],
                          capture_output=True, text=True)
    check(plot.returncode == 0 and (figures / "shear_stress.png").is_file(), "scripts/plot draws the ensemble")
    bad = subprocess.run(args[:3] + ["0-x"] + args[4:], capture_output=True, text=True)
    check(bad.returncode == 2 and "--seeds = 0-x" in bad.stderr, "a bad --seeds is refused naming the value")

print(f"ensemble checks: {len(failures)} failed")
sys.exit(1 if failures else 0)
