#!/usr/bin/python3
"""CTest mpi_task_farms: calibration trials and seed ensembles spread over MPI ranks give the results
of one process, for 1, 2 and 3 ranks (mpirun --oversubscribe on any machine).

Checked, on the reduced specimen (30 mm x 12 mm, 4D balls) and a lab curve written here:
- dem-calibrate under mpirun -n 1, 2, 3: trials.csv equals the run without mpirun in every column
  but the wall-clock seconds, comparison.csv and calibrated.ini byte for byte; summary.json records
  the rank count; the progress names the rank of each trial.
- a calibration stopped after three of its six trials (its trials.csv cut there and a half-written
  trial folder left, as a kill leaves them) and resumed on another rank count ends with the same
  trials.csv, reusing the three; trials whose folders hold their result but trials.csv does not
  are reused as well.
- an --out of another set-up, which the leading rank finds, and an input error that every rank
  finds end every rank with exit code 2 and one message, without MPI_Abort.
- dem-ensemble under mpirun -n 2 and 3: every seed's history.csv equals the one-process run byte
  for byte, and the seeds are shared out over the ranks.
- scripts/ensemble --mpi 2 writes the same ensemble.csv as --jobs 1.

OpenMPI refuses to run as root without its two allow variables: they are set here, for the
processes this test starts, not globally.

One simulation spread over ranks (dem-simple-shear, dem-consolidate): check_mpi_domains.py.

Usage: check_mpi_farms.py DEM_CALIBRATE DEM_ENSEMBLE MPIRUN
"""

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

calibrate, ensemble, mpirun = sys.argv[1:4]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def run(cmd, ranks=None):
    if ranks is not None:
        cmd = [mpirun, "--oversubscribe", "-n", str(ranks), *cmd]
    result = subprocess.run(cmd, capture_output=True, text=True, env=env)
    if result.returncode != 0:
        print(" ".join(cmd), "\n", result.stdout[-3000:], result.stderr[-3000:])
    return result


def trials(folder):
    with open(folder / "trials.csv") as f:
        return [{k: v for k, v in row.items() if k != "seconds"} for row in csv.DictReader(f)]


specimen = ["--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012", "--set", "output.fabric_strains=",
            "--set", "output.snapshot_strains=", "--threads", "1"]
# The dense specimen of test_calibration.cpp; friction only, one batch of three per search round,
# so that every round has work for three ranks.
calibration = [*specimen, "--set", "specimen.porosity=0.37", "--set", "generation.plate=fixed",
               "--set", "generation.friction=frictionless", "--set", "generation.rolling_friction=frictionless",
               "--set", "rings.vertical=fixed", "--set", "rings.stack_height=0.012", "--set", "output.every_strain=0.002",
               "--set", "calibration.cycles=1", "--set", "calibration.max_trials_per_stage=3",
               "--set", "calibration.batch_size=3", "--set", "ball_ball.friction=0.35", "--fit", "friction"]

with tempfile.TemporaryDirectory() as tmp:
    tmp = Path(tmp)
    lab = tmp / "lab.csv"
    with open(lab, "w") as f:  # a smooth hardening curve to 3 % strain
        f.write("shear_strain,shear_stress\n")
        for k in range(1, 31):
            f.write(f"{0.001 * k!r},{140e3 * (1 - math.exp(-0.001 * k / 0.006))!r}\n")

    serial = tmp / "serial"
    first = run([calibrate, "--lab", str(lab), "--out", str(serial), *calibration])
    check(first.returncode == 0, "dem-calibrate without mpirun exits 0")
    reference = trials(serial)
    check(len(reference) == 6, f"the calibration ran 6 trials ({len(reference)})")
    for ranks in (1, 2, 3):
        out = tmp / f"ranks{ranks}"
        result = run([calibrate, "--lab", str(lab), "--out", str(out), *calibration], ranks)
        check(result.returncode == 0, f"dem-calibrate on {ranks} rank(s) exits 0")
        if result.returncode != 0:
            continue
        check(trials(out) == reference, f"{ranks} rank(s): trials.csv equals the one-process run (but for seconds)")
        for name in ("comparison.csv", "calibrated.ini"):
            check((out / name).read_bytes() == (serial / name).read_bytes(), f"{ranks} rank(s): {name} byte for byte")
        summary = json.loads((out / "summary.json").read_text())
        check(summary.get("processes") == ranks, f"{ranks} rank(s): summary.json records processes = {ranks}")
        if ranks > 1:
            named = [f"on rank {r}" in result.stdout for r in range(ranks)]
            check(all(named), f"{ranks} ranks: the progress names every rank that ran a trial ({named})")

    # Stopped after three trials, resumed on two ranks.
    resumed = tmp / "resumed"
    shutil.copytree(tmp / "ranks3", resumed)
    with open(resumed / "trials.csv") as f:
        lines = f.readlines()
    (resumed / "trials.csv").write_text("".join(lines[:4]))
    for folder in (resumed / "trials").iterdir():
        if int(folder.name) > 3:
            shutil.rmtree(folder)
    (resumed / "trials" / "0004").mkdir()
    (resumed / "trials" / "0004" / "history.csv").write_text("shear_strain,shear_stress\n0.0")  # torn by the kill
    result = run([calibrate, "--lab", str(lab), "--out", str(resumed), *calibration], 2)
    check(result.returncode == 0 and "resuming: 3 finished trial(s)" in result.stdout,
          "a calibration cut after three trials resumes on another rank count")
    check(result.returncode == 0 and trials(resumed) == reference, "the resumed calibration ends with the same trials.csv")

    # Stopped after three trials were written to trials.csv, with three more finished in their
    # folders (a kill before the round's end on several ranks): those are taken, not run again.
    kept = tmp / "kept"
    shutil.copytree(tmp / "ranks3", kept)
    with open(kept / "trials.csv") as f:
        lines = f.readlines()
    (kept / "trials.csv").write_text("".join(lines[:4]))
    result = run([calibrate, "--lab", str(lab), "--out", str(kept), *calibration], 3)
    check(result.returncode == 0 and "6 trials (0 new, 6 reused)" in result.stdout and trials(kept) == reference,
          "trials finished in their folders but missing from trials.csv are reused, not run again")

    # The leading rank checks the folder and hands its verdict to every rank: all end alike.
    refused = run([calibrate, "--lab", str(lab), "--out", str(serial), *calibration, "--set", "calibration.eps_stress=2000"], 2)
    check(refused.returncode == 2 and refused.stderr.count("another calibration set-up") == 1 and "MPI_ABORT" not in refused.stderr,
          f"an --out of another set-up is refused on 2 ranks: exit code 2, said once, no abort (exit {refused.returncode})")

    # An input every rank checks alike: the same error, once, on every rank.
    alike = run([calibrate, "--lab", str(lab), "--out", str(tmp / "alike"), *calibration,
                 "--set", "calibration.rolling_target=dilatancy"], 2)
    check(alike.returncode == 2 and alike.stderr.count("has no volumetric strain column") == 1 and "MPI_ABORT" not in alike.stderr,
          f"an input error every rank meets: exit code 2, said once, no abort (exit {alike.returncode})")

    shear = [*specimen, "--set", "shear.target_strain=0.01"]
    one = tmp / "ensemble1"
    check(run([ensemble, "--seeds", "1-3", "--out", str(one), "--", *shear]).returncode == 0, "dem-ensemble without mpirun exits 0")
    for ranks in (2, 3):
        out = tmp / f"ensemble{ranks}"
        result = run([ensemble, "--seeds", "1-3", "--out", str(out), "--", *shear], ranks)
        check(result.returncode == 0, f"dem-ensemble on {ranks} ranks exits 0")
        same = [(out / f"seed_{s}" / "history.csv").read_bytes() == (one / f"seed_{s}" / "history.csv").read_bytes()
                for s in (1, 2, 3) if (out / f"seed_{s}" / "history.csv").is_file()]
        check(len(same) == 3 and all(same), f"{ranks} ranks: every seed's history.csv equals the one-process run ({same})")
        starts = [line for line in result.stdout.splitlines() if ": running on rank " in line]
        check(len(starts) == 3 and all(any(line.endswith(f"rank {r}") or f"rank {r}," in line for line in starts) for r in range(ranks)),
              f"{ranks} ranks: each seed ran once, and every rank ran one ({len(starts)} starts)")

    # scripts/ensemble --mpi 2: the same statistics as from one process.
    script = Path(__file__).resolve().parents[2] / "scripts" / "ensemble"
    launcher = dict(env, LIBDEM_MPIRUN=f"{mpirun} --oversubscribe --bind-to none")
    tables = []
    for name, how in (("script1", ["--jobs", "1"]), ("script2", ["--mpi", "2"])):
        result = subprocess.run([sys.executable, str(script), "--seeds", "1-2", *how, "--out", str(tmp / name), "--app", ensemble,
                                 "--", *shear], capture_output=True, text=True, env=launcher)
        if result.returncode != 0:
            print(result.stdout[-3000:], result.stderr[-3000:])
        tables.append((tmp / name / "ensemble.csv").read_bytes() if (tmp / name / "ensemble.csv").is_file() else None)
    check(tables[0] is not None and tables[0] == tables[1], "scripts/ensemble --mpi 2 writes the ensemble.csv of --jobs 1, byte for byte")

print(f"MPI task farm checks: {len(failures)} failed")
sys.exit(1 if failures else 0)
