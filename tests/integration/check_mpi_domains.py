#!/usr/bin/python3
"""CTest mpi_domains: one simulation spread over MPI ranks (World::spread_over) gives the results of
one process bit for bit, for 1, 2 and 3 ranks (mpirun --oversubscribe on any machine).

Checked:
- dem-bench on the 1,750-ball benchmark packing (generated here), with the ring-stack boundary
  (clumps, facet plates) and with the facet cylinder, and on the 14k packing with the cylinder: the
  state digest after 3,000 (500) steps (every particle's position, velocities, force and torque,
  every wall's force and displacement) equals the run's without mpirun on 1, 2 and 3 ranks (and,
  for 1,750 balls, on 2 ranks x 2 threads).
- dem-simple-shear on the 4D preset, reduced to a 45 mm specimen (683 balls) with 4,000 settling
  steps per generation stage (generation, consolidation, shear to 5 %; 3.6 s on one process, the
  full preset 16 s) on 1, 2 and 3 ranks:
  history.csv equals the one-process run's byte for byte; summary.json records the rank count.
- a 2-rank run killed during the generation and resumed from its restart file on 3 ranks ends with
  the same history.csv.
- dem-consolidate on 2 ranks: history.csv and fabric.csv equal the one-process run's.
- rings.vertical = sand, which reads the balls touching the rings inside each step, is refused on
  2 ranks before any work (exit code 2, one message, no folder).

OpenMPI refuses to run as root without its two allow variables: they are set here, for the
processes this test starts, not globally.

Usage: check_mpi_domains.py DEM_BENCH DEM_SIMPLE_SHEAR DEM_CONSOLIDATE MPIRUN
"""

import json
import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

bench, simple_shear, consolidate, mpirun = sys.argv[1:5]
env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMP_NUM_THREADS="1")
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def launched(cmd, ranks):
    return cmd if ranks is None else [mpirun, "--oversubscribe", "--bind-to", "none", "-n", str(ranks), *cmd]


def run(cmd, ranks=None):
    result = subprocess.run(launched(cmd, ranks), capture_output=True, text=True, env=env)
    if result.returncode != 0:
        print(" ".join(launched(cmd, ranks)), "\n", result.stdout[-3000:], result.stderr[-3000:])
    return result


def digest(result):
    lines = [line for line in result.stdout.splitlines() if line.startswith("state_digest: ")]
    return lines[0].split()[1] if lines else None


def read(path):
    return path.read_bytes() if path.is_file() else None


with tempfile.TemporaryDirectory() as work:
    tmp = Path(work)

    # The benchmark system: particles, clumps and walls, bit for bit.
    for size, steps, boundaries, layouts in (("1750", "3000", ("rings", "cylinder"), ((1, 1), (2, 1), (3, 1), (2, 2))),
                                             ("14k", "500", ("cylinder",), ((1, 1), (2, 1), (3, 1)))):
        packing = tmp / f"{size}.txt"
        check(run([bench, "--generate", size, "--out", str(packing), "--threads", "2"]).returncode == 0, f"dem-bench --generate {size}")
        for boundary in boundaries:
            args = [bench, "--packing", str(packing), "--steps", steps, "--boundary", boundary, "--segments", "60", "--digest"]
            one = digest(run(args))
            check(one is not None, f"{size}, {boundary}: the one-process run prints its state digest")
            for ranks, threads in layouts:
                result = run(args + ["--threads", str(threads)], ranks)
                check(result.returncode == 0 and f"ranks: {ranks}" in result.stdout and digest(result) == one,
                      f"{size}, {boundary}: {ranks} ranks x {threads} threads end in the one-process state ({digest(result)} vs {one})")

    # The (reduced) 4D preset to 5 % strain: the history of the whole test. At the earlier default
    # porosity 0.40, whose long friction schedule keeps the kill below inside the generation.
    preset = ["--preset", "4D", "--threads", "1", "--set", "specimen.porosity=0.40",
              "--set", "specimen.diameter=0.045", "--set", "generation.steps_per_stage=4000",
              "--set", "shear.target_strain=0.05", "--set", "output.snapshot_strains=",
              "--set", "output.fabric_strains=", "--set", "output.restart_every_steps=2000"]
    serial = tmp / "shear_serial"
    check(run([simple_shear, "--out", str(serial), *preset]).returncode == 0, "4D preset, one process")
    reference = read(serial / "history.csv")
    check(reference is not None and len(reference.splitlines()) > 5, "4D preset: history.csv has the shear's rows")
    for ranks in (1, 2, 3):
        out = tmp / f"shear{ranks}"
        result = run([simple_shear, "--out", str(out), *preset], ranks)
        check(result.returncode == 0 and read(out / "history.csv") == reference,
              f"4D preset on {ranks} ranks: history.csv equals the one-process run byte for byte")
        summary = json.loads(read(out / "summary.json") or b"{}")
        check(summary.get("processes") == ranks, f"4D preset on {ranks} ranks: summary.json records processes = {ranks}")
        check(result.stdout.count("generation done") == 1, f"4D preset on {ranks} ranks: one rank reports progress")

    # Killed during the generation on 2 ranks, resumed on 3.
    killed = tmp / "killed"
    process = subprocess.Popen(launched([simple_shear, "--out", str(killed), *preset], 2), stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, env=env)
    for line in process.stdout:
        if "[generation] stage 6/8" in line:
            break
    time.sleep(1.0)  # a restart file every 2000 steps: several are written by now
    process.send_signal(signal.SIGTERM)
    process.communicate()
    check(process.returncode != 0 and (killed / "restart.restart").is_file(),
          f"the 2-rank run stopped in the generation with a restart file (exit {process.returncode})")
    resumed = run([simple_shear, "--out", str(killed), "--from", str(killed / "restart.restart"), *preset], 3)
    check(resumed.returncode == 0 and read(killed / "history.csv") == reference,
          "killed on 2 ranks, resumed on 3: history.csv equals the one-process run byte for byte")

    # dem-consolidate on a reduced specimen.
    reduced = ["--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012", "--threads", "1"]
    check(run([consolidate, "--out", str(tmp / "cons1"), *reduced]).returncode == 0, "dem-consolidate, one process")
    result = run([consolidate, "--out", str(tmp / "cons2"), *reduced], 2)
    for name in ("history.csv", "fabric.csv"):
        check(result.returncode == 0 and read(tmp / "cons2" / name) is not None and read(tmp / "cons2" / name) == read(tmp / "cons1" / name),
              f"dem-consolidate on 2 ranks: {name} equals the one-process run byte for byte")

    # A ring mode that reads particles inside the step is refused before any work.
    sand = run([simple_shear, "--out", str(tmp / "sand"), *reduced, "--set", "rings.vertical=sand"], 2)
    check(sand.returncode == 2 and sand.stderr.count("rings.vertical = sand") == 1 and "MPI_ABORT" not in sand.stderr
          and not (tmp / "sand").exists(),
          f"rings.vertical = sand on 2 ranks: exit code 2, said once, no folder (exit {sand.returncode})")

print(f"MPI domain checks: {len(failures)} failed")
sys.exit(1 if failures else 0)
