#!/usr/bin/python3
"""Kill-and-resume and crash-safety checks of dem-simple-shear on a reduced specimen.

Usage: kill_resume.py DEM_SIMPLE_SHEAR WORK_DIR [SEED]   (tests/ctest/kill_resume.cmake runs it)

1. In each stage (generation, consolidation, shear): run A goes through uninterrupted; run B is
   killed with SIGKILL at a random moment of that stage, then resumed with --from
   B/restart.restart (its log must name the stage). history.csv, fabric.csv and the snapshots of B
   must equal A's byte for byte, and final.restart must hold the same World state, field by
   field, and the same protocol block except wall_seconds (the run's wall-clock time). A
   temporary file planted as a killed writer would leave it is removed by the resumed run.
2. A truncated and a corrupted (one flipped byte) restart file are refused by --from with exit
   code 2 and a message naming the file and the problem.
3. Output folders: refused runs (wrong stage, another run in --out, --from a folder, a FIFO or a
   device, a refused --replace, another diameter) exit 2 and leave --out as it was; --replace
   removes the old run as a whole and nothing else (a user's file named like a temporary stays); a
   second run into a folder in use stops at once while the first finishes.
4. Atomic outputs: runs that rewrite history.csv every few steps are killed at random moments;
   history.csv must always be a complete table (header, whole rows, final newline). Temporary
   files may be left behind by SIGKILL; they are not checked.

The random delays come from SEED (default 8, or LIBDEM_KILL_SEED), printed for reproduction: a
seed gives the same delays, though the step they land on depends on the machine's speed. The World
state comparison reads the field layout of io::write_world_state (world_fields below): a change of
that layout must be made there too. Only the Python standard library is used.
"""
import json
import os
import random
import shutil
import signal
import struct
import subprocess
import sys
import time

SPECIMEN = ["--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012",
            "--set", "shear.target_strain=0.04", "--set", "output.restart_every_steps=200",
            "--set", "output.snapshot_strains=0,0.04",
            "--threads", "1"]
RUN_TIMEOUT = 900  # s, one whole run; the reduced specimen takes well under a minute in Release
HEADER = 8 + 4 + 8  # restart file: magic, format version, payload size (io/checkpoint.cpp)


def fail(message):
    print("FAIL: " + message, flush=True)
    sys.exit(1)


def run(program, args, log_name):
    with open(log_name, "w") as log:
        return subprocess.run([program] + args, stdout=log, stderr=subprocess.STDOUT, timeout=RUN_TIMEOUT).returncode


def read(path):
    with open(path, "rb") as f:
        return f.read()


def restart_parts(path):
    """(protocol text, World state bytes) of a restart file."""
    data = read(path)
    payload = data[HEADER:-8]
    (text_size,) = struct.unpack_from("<Q", payload, 0)
    return payload[8:8 + text_size].decode(), payload[8 + text_size:]


def world_fields(state):
    """{name: bytes} of the fields of a World state, in the order of io::write_world_state
    (io/world_state.cpp): u64 counts before arrays and strings, doubles and ints raw."""
    fields, at = {}, 0

    def take(name, size):
        nonlocal at
        if at + size > len(state):
            fail(f"final.restart: World state ends inside '{name}': kill_resume.py's layout is out of date")
        fields[name] = state[at:at + size]
        at += size
        return fields[name]

    def count(name):
        return struct.unpack("<Q", take(name + ".count", 8))[0]

    def array(name, item_size):
        take(name, count(name) * item_size)

    for kind in ("ball_ball", "ball_facet", "ball_pebble"):
        array("law." + kind, 1)
    for name, size in (("time", 8), ("steps", 8), ("dt", 8), ("time_step", 8), ("time_step_safety", 8),
                       ("local_damping", 8), ("gravity", 24), ("skin", 8), ("sort_every", 4),
                       ("max_overlap_ratio", 8), ("max_step_travel_ratio", 8), ("pebble_pebble_contacts", 1)):
        take(name, size)
    for name, size in (("x", 24), ("v", 24), ("w", 24), ("f", 24), ("t", 24), ("radius", 8), ("mass", 8),
                       ("inv_mass", 8), ("inv_inertia", 8), ("id", 4), ("group", 4), ("clump", 4), ("fixed", 1)):
        array("particles." + name, size)
    for c in range(count("clumps")):
        take(f"clump{c}.body", 8 + 3 * 24 + 32 + 72 + 1)
        array(f"clump{c}.pebbles", 4)
        array(f"clump{c}.pebble_offsets", 24)
        take(f"clump{c}.loads", 5 * 24)
    walls = count("walls")
    for w in range(walls):
        array(f"wall{w}.name", 1)
        array(f"wall{w}.vertices", 24)
        array(f"wall{w}.triangles", 12)
        take(f"wall{w}.body", 4 * 24 + 8 + 2 * 24 + 4 + 8)

    def contact_states(prefix):
        stride = struct.unpack("<Q", take(prefix + ".stride", 8))[0]
        take(prefix + ".states", count(prefix + ".states") * stride)

    for pairs in ("ball_ball", "ball_pebble"):
        for name, size in (("first", 4), ("second", 4), ("force", 24), ("torque_first", 24), ("torque_second", 24),
                           ("normal_force", 8)):
            array(f"{pairs}.{name}", size)
        contact_states(pairs)
    def wall_contacts(prefix):
        for name, size in (("ball", 4), ("wall", 4), ("triangle_begin", 4), ("triangle_end", 4), ("triangles", 4),
                           ("force", 24), ("torque_ball", 24), ("point", 24), ("moment", 24), ("normal_force", 8),
                           ("normal_stiffness", 8)):
            array(f"{prefix}.{name}", size)
        contact_states(prefix)

    wall_contacts("wall_contacts")
    for name, size in (("bb_offsets", 4), ("bb_entries", 4), ("bp_offsets", 4), ("bp_entries", 4),
                       ("x_at_rebuild", 24), ("wall_disp_at_rebuild", 24)):
        array(name, size)
    for name, size in (("need_rebuild", 1), ("rebuilds", 8), ("max_travel_sq", 8), ("max_wall_travel", 8),
                       ("skin_", 8)):
        take(name, size)
    for w in range(walls):  # format 2: the walls' analytic surfaces and their contacts
        take(f"wall{w}.surface", 1 + 2 * 24 + 8)
    wall_contacts("surface_contacts")
    if take("periodic_cell", 1) == b"\x01":  # format 3: the periodic cell
        take("cell", 24 + 2 * 72 + 3 + 1 + 72)  # origin, h, L, axes, re-map flag, h at rebuild
        array("ball_ball.image", 1)
        array("ball_pebble.image", 1)
    for name, size in (("first", 4), ("second", 4), ("radius", 8), ("normal_stiffness", 8),  # format 4: bonds
                       ("shear_stiffness", 8), ("tensile_strength", 8), ("cohesion", 8), ("friction_angle", 8),
                       ("normal_force", 8), ("shear_force", 24), ("twist_moment", 8), ("bend_moment", 24),
                       ("status", 1)):
        array("bonds." + name, size)
    if at != len(state):
        fail(f"final.restart: {len(state) - at} bytes after the last World field: "
             "kill_resume.py's layout is out of date")
    return fields


def compare_world_states(a, b):
    fields_a, fields_b = world_fields(a), world_fields(b)
    for name in fields_a:
        if fields_a[name] != fields_b.get(name):
            fail(f"final.restart: World field '{name}' of the resumed run differs from the uninterrupted run's")
    return len(fields_a)


def without_wall_clock(protocol):
    """The protocol state (a JSON object) without the run's wall-clock time."""
    state = json.loads(protocol)
    state.pop("wall_seconds")
    return state


def check_complete_csv(path, context):
    """A complete table: header, rows of as many numbers as columns, final newline."""
    data = read(path)
    if not data.endswith(b"\n"):
        fail(f"{context}: {path} does not end with a newline (torn write): ...{data[-80:]!r}")
    lines = data.decode().splitlines()
    columns = lines[0].split(",")
    for number, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != len(columns):
            fail(f"{context}: {path} line {number} has {len(cells)} cells, the header {len(columns)}")
        try:
            [float(c) for c in cells]
        except ValueError:
            fail(f"{context}: {path} line {number} is not all numbers: {line!r}")
    return len(lines) - 1


def marks(out, log_path):
    """Which points run `out` has passed: its first restart file, the end of the generation (its
    log line), consolidated.restart, final.restart."""
    log = read(log_path).decode(errors="replace") if os.path.exists(log_path) else ""
    return {"restart": os.path.exists(os.path.join(out, "restart.restart")),
            "generated": "generation done" in log,
            "consolidated": os.path.exists(os.path.join(out, "consolidated.restart")),
            "final": os.path.exists(os.path.join(out, "final.restart"))}


def timed_run(program, args, out, log_path):
    """Runs to the end, noting when each mark was first passed (s from the start)."""
    start = time.monotonic()
    seen = {}
    with open(log_path, "w") as log:
        process = subprocess.Popen([program] + args + ["--out", out], stdout=log, stderr=subprocess.STDOUT)
        while process.poll() is None:
            for name, passed in marks(out, log_path).items():
                if passed and name not in seen:
                    seen[name] = time.monotonic() - start
            if time.monotonic() - start > RUN_TIMEOUT:
                process.kill()
                fail(f"run {out} did not end within {RUN_TIMEOUT} s")
            time.sleep(0.003)
    if process.returncode != 0:
        fail(f"run {out} failed (exit {process.returncode}); see {log_path}")
    for name, passed in marks(out, log_path).items():
        seen.setdefault(name, time.monotonic() - start)
    return seen


def kill_and_resume(program, work, rng, stage, args, start_mark, end_mark):
    """Run A goes through; run B is killed between `start_mark` and `end_mark` (the stage
    `stage` of the resumed run's log) and resumed from B/restart.restart; their outputs and
    final.restart must be the same."""
    a, b = os.path.join(work, stage + "-A"), os.path.join(work, stage + "-B")
    seen = timed_run(program, args, a, a + ".log")
    window = seen[end_mark] - seen[start_mark]
    print(f"{stage}: run A passed {start_mark} at {seen[start_mark]:.2f} s and {end_mark} at {seen[end_mark]:.2f} s",
          flush=True)

    # Killed somewhere between 15 % and 75 % of the window; if a faster run B passes the end mark
    # first anyway (a busy machine slowed run A), try again sooner.
    delay = rng.uniform(0.15, 0.75) * window
    for attempt in range(5):
        shutil.rmtree(b, ignore_errors=True)
        log_path = b + ".log"
        with open(log_path, "w") as log:
            process = subprocess.Popen([program] + args + ["--out", b], stdout=log, stderr=subprocess.STDOUT)
            started = time.monotonic()
            while not marks(b, log_path)[start_mark]:
                if process.poll() is not None or time.monotonic() - started > RUN_TIMEOUT:
                    fail(f"{stage}: run B ended (exit {process.poll()}) before passing {start_mark}")
                time.sleep(0.003)
            time.sleep(delay)
            process.send_signal(signal.SIGKILL)
            process.wait()
        if not marks(b, log_path)[end_mark]:
            break
        print(f"{stage}: run B passed {end_mark} before the kill at +{delay:.2f} s; again with half the delay", flush=True)
        delay /= 2
    else:
        fail(f"{stage}: run B always passed {end_mark} before the kill")
    print(f"{stage}: run B killed {delay:.2f} s after {start_mark}", flush=True)

    # A killed writer may leave a temporary file; the next run in the folder removes it.
    leftover = os.path.join(b, "history.csv.tmp.4194303")
    with open(leftover, "w") as f:
        f.write("time,step\n1,")
    resumed_log = os.path.join(work, stage + "-B-resumed.log")
    code = run(program, args + ["--out", b, "--from", os.path.join(b, "restart.restart")], resumed_log)
    if code != 0:
        fail(f"{stage}: the resumed run failed (exit {code}); see {resumed_log}")
    text = read(resumed_log).decode()
    if f"({stage}," not in text:
        fail(f"{stage}: the restart file the kill left is not one of the {stage} stage: {text.splitlines()[0]!r}")
    if os.path.exists(leftover) or "temporary file(s) left by a killed run" not in text:
        fail(f"{stage}: the resumed run did not remove the temporary file a killed run left")
    snapshots = sorted(os.listdir(os.path.join(a, "snapshots")))
    if sorted(os.listdir(os.path.join(b, "snapshots"))) != snapshots:
        fail(f"{stage}: the snapshot files of the resumed run differ from the uninterrupted run's")
    for name in ["history.csv", "fabric.csv"] + [os.path.join("snapshots", f) for f in snapshots]:
        if read(os.path.join(a, name)) != read(os.path.join(b, name)):
            fail(f"{stage}: {name} of the killed-and-resumed run differs from the uninterrupted run's")
    protocol_a, state_a = restart_parts(os.path.join(a, "final.restart"))
    protocol_b, state_b = restart_parts(os.path.join(b, "final.restart"))
    fields = compare_world_states(state_a, state_b)
    if without_wall_clock(protocol_a) != without_wall_clock(protocol_b):
        fail(f"{stage}: final.restart: protocol state differs:\n{protocol_a}\n---\n{protocol_b}")
    rows = check_complete_csv(os.path.join(a, "history.csv"), "run A")
    print(f"{stage}: resumed run equals the uninterrupted one: history.csv ({rows} rows), fabric.csv, {len(snapshots)} "
          f"snapshot files, final World state ({fields} fields, {len(state_a)} bytes)", flush=True)
    return a, seen["final"] - seen["consolidated"]


def damaged_restart_files(program, work, a):
    good = read(os.path.join(a, "restart.restart"))
    out = os.path.join(work, "damaged")
    os.makedirs(out)
    flipped = bytearray(good)
    flipped[len(good) // 2] ^= 0x10
    for name, data, problem in (("truncated.restart", good[:len(good) // 2], "truncated"),
                                ("corrupted.restart", bytes(flipped), "checksum")):
        path = os.path.join(out, name)
        with open(path, "wb") as f:
            f.write(data)
        result = subprocess.run([program] + SPECIMEN + ["--out", os.path.join(out, "run"), "--from", path],
                                capture_output=True, text=True, timeout=RUN_TIMEOUT)
        if result.returncode != 2 or problem not in result.stderr or path not in result.stderr:
            fail(f"{name}: expected exit 2 and a message naming the file and '{problem}', got exit "
                 f"{result.returncode}: {result.stderr.strip()!r}")
        print(f"{name} refused: {result.stderr.strip()}", flush=True)


def atomic_history(program, work, a, rng, shear_seconds, kills=8):
    """Each run restarts from the consolidated state and rewrites history.csv every ~10 steps."""
    out = os.path.join(work, "atomic")
    shutil.copytree(a, out)  # --from consolidated.restart keeps the history rows up to that point
    os.remove(os.path.join(out, "final.restart"))  # as a run killed in its shear leaves the folder
    args = SPECIMEN + ["--set", "output.every_strain=0.0001", "--out", out,
                       "--from", os.path.join(out, "consolidated.restart")]
    history = os.path.join(out, "history.csv")
    for k in range(kills):
        before = os.path.getmtime(history)
        process = subprocess.Popen([program] + args, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
        # Wait for the first rewrite, so that the kill lands among repeated writes.
        start = time.monotonic()
        while os.path.getmtime(history) == before:
            if process.poll() is not None or time.monotonic() - start > RUN_TIMEOUT:
                fail(f"atomic outputs: run {k} never rewrote history.csv (exit {process.poll()})")
            time.sleep(0.002)
        delay = rng.uniform(0.0, 0.8) * shear_seconds
        time.sleep(delay)
        process.send_signal(signal.SIGKILL)
        process.wait()
        rows = check_complete_csv(history, f"atomic outputs, kill {k} at +{delay:.3f} s")
        print(f"atomic outputs: kill {k} at +{delay:.3f} s after the first rewrite: history.csv complete, {rows} rows",
              flush=True)


def output_folders(program, work, a):
    """--out is claimed before any work: refusals leave it as it was, --replace removes the old run
    as a whole, a second run into a busy folder stops at once."""
    consolidate = os.path.join(os.path.dirname(program), "dem-consolidate")
    out = os.path.join(work, "folders")
    other = os.path.join(out, "other")
    os.makedirs(other)
    old = {"history.csv": b"time,step\n0,0\n", "consolidated.restart": b"another specimen"}
    for name, data in old.items():
        with open(os.path.join(other, name), "wb") as f:
            f.write(data)

    def unchanged(context):
        if sorted(os.listdir(other)) != sorted(list(old) + [".lock"]) and sorted(os.listdir(other)) != sorted(old):
            fail(f"{context}: the refused run changed the files in {other}: {sorted(os.listdir(other))}")
        for name, data in old.items():
            if read(os.path.join(other, name)) != data:
                fail(f"{context}: the refused run changed {name}")

    def refused(args, expect, context, app=program):
        result = subprocess.run([app] + SPECIMEN + args, capture_output=True, text=True, timeout=RUN_TIMEOUT)
        if result.returncode != 2 or expect not in result.stderr:
            fail(f"{context}: expected exit 2 and '{expect}', got exit {result.returncode}: {result.stderr.strip()!r}")
        print(f"{context}: refused: {result.stderr.strip()}", flush=True)

    refused(["--out", other, "--from", os.path.join(a, "final.restart")], "stage 4",
            "dem-consolidate --from a sheared restart", app=consolidate)
    unchanged("wrong stage")
    refused(["--out", other, "--from", os.path.join(a, "consolidated.restart")], "--replace",
            "--from another folder into one holding another run")
    unchanged("occupied folder")
    refused(["--out", other, "--from", a], "a folder", "--from a folder")
    unchanged("--from a folder")
    refused(["--out", other, "--from", os.path.join(a, "consolidated.restart"), "--set", "specimen.diameter=0.042"],
            "specimen.diameter = 0.042 here, 0.03 in the file", "--from with another diameter")
    unchanged("another diameter")
    cyclic = os.path.join(os.path.dirname(program), "dem-cyclic-shear")
    refused(["--out", other, "--from", os.path.join(a, "final.restart"), "--replace"], "stage = 4",
            "dem-cyclic-shear --replace --from a sheared restart", app=cyclic)
    unchanged("a refused --replace")
    fifo = os.path.join(out, "pipe.restart")
    os.mkfifo(fifo)
    refused(["--out", other, "--from", fifo], "is a FIFO", "--from a FIFO")
    refused(["--out", other, "--from", "/dev/zero"], "is a character device", "--from /dev/zero")
    unchanged("--from a FIFO or a device")
    # A user's file named like a killed run's temporary is not one: --replace leaves it.
    ended = subprocess.Popen(["true"])
    ended.wait()
    user_file = os.path.join(other, f"notes.txt.tmp.{ended.pid}")
    with open(user_file, "w") as f:
        f.write("the user's own")
    code = run(program, SPECIMEN + ["--out", other, "--from", os.path.join(a, "consolidated.restart"), "--replace"],
               os.path.join(out, "replace.log"))
    if not os.path.exists(user_file):
        fail("--replace removed a user's file named like a temporary file")
    if code != 0 or os.path.exists(os.path.join(other, "consolidated.restart")):
        fail(f"--replace: exit {code}; the old run's consolidated.restart must be gone: {sorted(os.listdir(other))}")
    if read(os.path.join(other, "history.csv")) != read(os.path.join(a, "history.csv")):
        fail("--replace: the new shear of A's specimen must have A's history")
    print("--replace: the old run's files were removed and the new run's written", flush=True)

    # A second --replace removes what the manifest of the run before lists, and nothing else: a
    # user's files beside the results and inside snapshots/ stay, under any name.
    mine = {os.path.join(other, "my_notes.txt"): b"the user's notes",
            os.path.join(other, "snapshots", "my_view.pvsm"): b"the user's ParaView state",
            os.path.join(other, "snapshots", "balls_strain_99.0.vtp"): b"the user's own copy"}
    for path, data in mine.items():
        with open(path, "wb") as f:
            f.write(data)
    code = run(program, SPECIMEN + ["--out", other, "--replace", "--set", "output.snapshot_strains=0.04"],
               os.path.join(out, "replace2.log"))
    if code != 0 or any(read(path) != data for path, data in mine.items()):
        fail(f"a second --replace (exit {code}) removed or changed a user's file: {sorted(os.listdir(other))}")
    if os.path.exists(os.path.join(other, "snapshots", "balls_strain_00.0.vtp")):
        fail("a second --replace left a snapshot of the run it replaced")
    listed = json.loads(read(os.path.join(other, "manifest.json")))["files"]
    if any(name.startswith("my_") or "99.0" in name for name in listed) or "snapshots/balls_strain_04.0.vtp" not in listed:
        fail(f"manifest.json must list the run's files and no user's: {listed}")
    print("a second --replace kept the user's files in --out and snapshots/", flush=True)

    # A run that ended, run again from its consolidated specimen in its own folder: refused (two
    # runs' files would stand side by side until it ends), the folder left as it was.
    again = os.path.join(out, "again")
    shutil.copytree(a, again)
    before = {name: read(os.path.join(again, name)) for name in ("history.csv", "summary.json", "final.restart")}
    refused(["--out", again, "--from", os.path.join(again, "consolidated.restart")], "holds a run that ended",
            "a re-shear into the specimen's own folder")
    if any(read(os.path.join(again, name)) != data for name, data in before.items()):
        fail("a refused re-shear into its own folder changed its files")

    busy = os.path.join(out, "busy")
    with open(os.path.join(out, "busy.log"), "w") as log:
        first = subprocess.Popen([program] + SPECIMEN + ["--out", busy], stdout=log, stderr=subprocess.STDOUT)
        start = time.monotonic()
        while not os.path.exists(os.path.join(busy, "restart.restart")):
            if first.poll() is not None or time.monotonic() - start > RUN_TIMEOUT:
                fail(f"the first run into {busy} ended (exit {first.poll()}) before writing a restart file")
            time.sleep(0.003)
        refused(["--out", busy], "in use by another run (pid " + str(first.pid), "a second run into a busy folder")
        if first.wait(timeout=RUN_TIMEOUT) != 0:
            fail(f"the first run into {busy} failed after the second was refused (exit {first.returncode})")
    print("a second run into a busy folder stopped at once; the first finished", flush=True)

    # Two ensembles into one folder: the second finds the running seed's folder locked and leaves
    # its run.log and results alone.
    ensemble = os.path.join(os.path.dirname(program), "dem-ensemble")
    if not os.access(ensemble, os.X_OK):
        print("dem-ensemble not built: its busy seed folder not checked", flush=True)
        return
    shared = os.path.join(out, "ensemble")
    seed_log = os.path.join(shared, "seed_1", "run.log")
    with open(os.path.join(out, "ensemble-first.log"), "w") as log:
        first = subprocess.Popen([ensemble, "--seeds", "1", "--out", shared, "--"] + SPECIMEN, stdout=log,
                                 stderr=subprocess.STDOUT)
        start = time.monotonic()
        while not os.path.exists(os.path.join(shared, "seed_1", "restart.restart")):
            if first.poll() is not None or time.monotonic() - start > RUN_TIMEOUT:
                fail(f"the first ensemble into {shared} ended (exit {first.poll()}) before writing a restart file")
            time.sleep(0.003)
        log_start = read(seed_log)[:200]
        second = subprocess.run([ensemble, "--seeds", "1", "--out", shared, "--"] + SPECIMEN, capture_output=True,
                                text=True, timeout=RUN_TIMEOUT)
        if second.returncode != 1 or "in use by another run (pid " + str(first.pid) not in second.stdout:
            fail(f"a second ensemble into a busy seed folder: expected exit 1 naming pid {first.pid}, got exit "
                 f"{second.returncode}: {second.stdout.strip()!r} {second.stderr.strip()!r}")
        if read(seed_log)[:200] != log_start:
            fail("a second ensemble rewrote the running seed's run.log")
        if first.wait(timeout=RUN_TIMEOUT) != 0:
            fail(f"the first ensemble failed after the second was refused (exit {first.returncode})")
        if b"in use by another run" in read(seed_log):
            fail("the second ensemble wrote into the running seed's run.log")
    print("a second ensemble into a busy seed folder left it alone; the first finished", flush=True)


def main():
    if len(sys.argv) not in (3, 4):
        print(__doc__)
        sys.exit(2)
    program, work = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    seed = int(sys.argv[3]) if len(sys.argv) == 4 else int(os.environ.get("LIBDEM_KILL_SEED", "8"))
    print(f"seed {seed} (set LIBDEM_KILL_SEED to vary the kill moments)", flush=True)
    rng = random.Random(seed)
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    kill_and_resume(program, work, rng, "generating", SPECIMEN, "restart", "generated")
    # A consolidation long enough for restart files during it.
    kill_and_resume(program, work, rng, "consolidating", SPECIMEN + ["--set", "consolidation.settle_steps=20000"],
                    "generated", "consolidated")
    a, shear_seconds = kill_and_resume(program, work, rng, "shearing", SPECIMEN, "consolidated", "final")
    damaged_restart_files(program, work, a)
    output_folders(program, work, a)
    atomic_history(program, work, a, rng, shear_seconds)
    shutil.rmtree(work)  # kept on failure, for the logs
    print("kill_resume: all checks passed")


if __name__ == "__main__":
    main()
