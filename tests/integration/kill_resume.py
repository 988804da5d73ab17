#!/usr/bin/python3
"""Kill-and-resume and crash-safety checks of dem-simple-shear on a reduced specimen.

Usage: kill_resume.py DEM_SIMPLE_SHEAR WORK_DIR [SEED]   (tests/ctest/kill_resume.cmake runs it)

1. Run A goes through uninterrupted. Run B is killed with SIGKILL at a random moment of its shear
   (after its first periodic restart file appeared), then resumed with --from B/restart.restart.
   history.csv, fabric.csv and the snapshots of B must equal A's byte for byte, and final.restart
   must hold the same World state, field by field, and the same protocol block except
   wall_seconds (the run's wall-clock time).
2. A truncated and a corrupted (one flipped byte) restart file are refused by --from with exit
   code 2 and a message naming the file and the problem.
3. Atomic outputs: runs that rewrite history.csv every few steps are killed at random moments;
   history.csv must always be a complete table (header, whole rows, final newline). Temporary
   files may be left behind by SIGKILL; they are not checked.

The random delays come from SEED (default 8, or LIBDEM_KILL_SEED), printed for reproduction: a
seed gives the same delays, though the step they land on depends on the machine's speed. The World
state comparison reads the field layout of World::save_state (world_fields below): a change of
that layout must be made there too. Only the Python standard library is used.
"""
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


def wait_for(path, process, timeout=RUN_TIMEOUT):
    """Polls until `path` exists; fails if the process ends first."""
    start = time.monotonic()
    while not os.path.exists(path):
        if process.poll() is not None:
            fail(f"the run ended (exit {process.returncode}) before {path} appeared")
        if time.monotonic() - start > timeout:
            process.kill()
            fail(f"{path} did not appear within {timeout} s")
        time.sleep(0.005)
    return time.monotonic()


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
    """{name: bytes} of the fields of a World state, in the order of World::save_state
    (core/world_checkpoint.cpp): u64 counts before arrays and strings, doubles and ints raw."""
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
    for w in range(count("walls")):
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
    for name, size in (("ball", 4), ("wall", 4), ("triangle_begin", 4), ("triangle_end", 4), ("triangles", 4),
                       ("force", 24), ("torque_ball", 24), ("point", 24), ("moment", 24), ("normal_force", 8),
                       ("normal_stiffness", 8)):
        array("wall_contacts." + name, size)
    contact_states("wall_contacts")
    for name, size in (("bb_offsets", 4), ("bb_entries", 4), ("bp_offsets", 4), ("bp_entries", 4),
                       ("x_at_rebuild", 24), ("wall_disp_at_rebuild", 24)):
        array(name, size)
    for name, size in (("need_rebuild", 1), ("rebuilds", 8), ("max_travel_sq", 8), ("max_wall_travel", 8),
                       ("skin_", 8)):
        take(name, size)
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
    return [line for line in protocol.splitlines() if not line.startswith("wall_seconds ")]


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


def kill_and_resume(program, work, rng):
    a, b = os.path.join(work, "A"), os.path.join(work, "B")
    # Run A, timed so that run B's kill can be placed inside the shear.
    process = subprocess.Popen([program] + SPECIMEN + ["--out", a], stdout=open(os.path.join(work, "A.log"), "w"),
                               stderr=subprocess.STDOUT)
    first_restart = wait_for(os.path.join(a, "restart.restart"), process)
    if process.wait(timeout=RUN_TIMEOUT) != 0:
        fail(f"run A failed (exit {process.returncode}); see {work}/A.log")
    shear_seconds = time.monotonic() - first_restart
    print(f"run A: shear took {shear_seconds:.1f} s after the first restart file", flush=True)

    # Run B, killed somewhere between 15 % and 75 % of the shear: late enough that periodic restart
    # files and history rows have been written since the first one, early enough to land mid-shear.
    # If a faster run B finishes first anyway (a busy machine slowed run A), try again sooner.
    delay = rng.uniform(0.15, 0.75) * shear_seconds
    for attempt in range(4):
        shutil.rmtree(b, ignore_errors=True)
        process = subprocess.Popen([program] + SPECIMEN + ["--out", b], stdout=open(os.path.join(work, "B.log"), "w"),
                                   stderr=subprocess.STDOUT)
        wait_for(os.path.join(b, "restart.restart"), process)
        time.sleep(delay)
        if process.poll() is None:
            break
        print(f"run B ended before the kill at +{delay:.2f} s; again with half the delay", flush=True)
        delay /= 2
    else:
        fail("run B always ended before the kill: it cannot be killed mid-shear")
    process.send_signal(signal.SIGKILL)
    process.wait()
    if os.path.exists(os.path.join(b, "final.restart")):
        fail("run B wrote final.restart before it was killed: the kill did not land mid-shear")
    print(f"run B: SIGKILL {delay:.2f} s after its first restart file", flush=True)

    code = run(program, SPECIMEN + ["--out", b, "--from", os.path.join(b, "restart.restart")],
               os.path.join(work, "B-resumed.log"))
    if code != 0:
        fail(f"the resumed run failed (exit {code}); see {work}/B-resumed.log")
    snapshots = sorted(os.listdir(os.path.join(a, "snapshots")))
    if sorted(os.listdir(os.path.join(b, "snapshots"))) != snapshots:
        fail("the snapshot files of the resumed run differ from the uninterrupted run's")
    for name in ["history.csv", "fabric.csv"] + [os.path.join("snapshots", f) for f in snapshots]:
        if read(os.path.join(a, name)) != read(os.path.join(b, name)):
            fail(f"{name} of the killed-and-resumed run differs from the uninterrupted run's")
    protocol_a, state_a = restart_parts(os.path.join(a, "final.restart"))
    protocol_b, state_b = restart_parts(os.path.join(b, "final.restart"))
    fields = compare_world_states(state_a, state_b)
    if without_wall_clock(protocol_a) != without_wall_clock(protocol_b):
        fail(f"final.restart: protocol state differs:\n{protocol_a}\n---\n{protocol_b}")
    rows = check_complete_csv(os.path.join(a, "history.csv"), "run A")
    print(f"resumed run equals the uninterrupted one: history.csv ({rows} rows), fabric.csv, {len(snapshots)} "
          f"snapshot files, final World state ({fields} fields, {len(state_a)} bytes)", flush=True)
    return a, shear_seconds


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
    a, shear_seconds = kill_and_resume(program, work, rng)
    damaged_restart_files(program, work, a)
    atomic_history(program, work, a, rng, shear_seconds)
    shutil.rmtree(work)  # kept on failure, for the logs
    print("kill_resume: all checks passed")


if __name__ == "__main__":
    main()
