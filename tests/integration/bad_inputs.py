#!/usr/bin/env python3
"""Bad inputs to the apps, as a table: each case runs one app with one bad input and expects exit
code 2 (refused before any work), every expected piece of text in its message, a message of at
most MAX_MESSAGE bytes with no control byte, and its --out folder not created.

The cases are the two input audits': files that are not regular files or not what they claim,
absurd physical values, lab curves that cannot be read as they claim, keys that do not apply,
restart files used by the wrong test. Each app must refuse at the door: no case may take more
than a few tenths of a second, so the table runs in seconds.

Usage: bad_inputs.py APPS_DIR WORK_DIR
"""
import os
import shutil
import subprocess
import sys

MAX_MESSAGE = 2000  # bytes: quoted inputs are shortened excerpts, never echoed whole
SMALL = ["--preset", "4D", "--set", "specimen.diameter=0.03", "--set", "specimen.height=0.012", "--threads", "1"]


def fail(message):
    print(f"FAILED: {message}", flush=True)
    sys.exit(1)


def write(path, data):
    with open(path, "wb") as f:
        f.write(data)
    return path


def cases(work, files):
    """(name, app, arguments, expected texts). OUT in the arguments is the case's --out folder."""
    s = lambda key_value: ["--set", key_value]
    return [
        # Files that are not regular files, or not files of their kind.
        ("--from a FIFO", "dem-simple-shear", SMALL + ["--from", files["fifo"]], ["--from", "is a FIFO"]),
        ("--from /dev/zero", "dem-simple-shear", SMALL + ["--from", "/dev/zero"], ["--from", "character device"]),
        ("--from a folder", "dem-simple-shear", SMALL + ["--from", work], ["--from", "a folder"]),
        ("--from a text file", "dem-simple-shear", SMALL + ["--from", files["notes"]], ["notes.txt", "not a libdem restart file"]),
        ("--config a FIFO", "dem-simple-shear", SMALL + ["--config", files["fifo.ini"]], ["fifo.ini", "FIFO"]),
        ("--config a folder", "dem-simple-shear", SMALL + ["--config", files["folder.ini"]], ["folder.ini", "folder"]),
        ("--config without extension", "dem-simple-shear", SMALL + ["--config", files["notes"]], [".ini or .json"]),
        ("--config with NUL bytes", "dem-simple-shear", SMALL + ["--config", files["nul.ini"]],
         ["nul.ini", "specimen.porosity", "0.4\\x00"]),
        ("--lab a FIFO", "dem-calibrate", SMALL + ["--lab", files["fifo"]], ["--lab", "is a FIFO"]),
        ("--lab a folder", "dem-calibrate", SMALL + ["--lab", work], ["--lab", "a folder"]),
        # Lab curves that cannot be read as they claim.
        ("lab curve of two points", "dem-calibrate", SMALL + ["--lab", files["two_points.csv"]], ["lab", "points"]),
        ("Pa values under a kPa header", "dem-calibrate", SMALL + ["--lab", files["pa_as_kpa.csv"]],
         ["shear_stress_kPa", "Pa"]),
        # Absurd physical values: the key, the value and the range.
        ("density 1e-300", "dem-simple-shear", SMALL + s("specimen.density=1e-300"), ["specimen.density", "1e-300"]),
        ("ring pebbles of 1 m", "dem-simple-shear", SMALL + s("rings.pebble_diameter=1"), ["rings.pebble_diameter", "= 1", "a quarter of specimen.height"]),
        ("strain rate 1e308", "dem-simple-shear", SMALL + s("shear.strain_rate=1e308"), ["shear.strain_rate", "1e308", "[0, 1e+06]"]),
        ("modulus 1e20 Pa", "dem-simple-shear", SMALL + s("ball_ball.effective_modulus=1e20"),
         ["ball_ball.effective_modulus", "1e20", "1e+13"]),
        ("friction 1e6", "dem-simple-shear", SMALL + s("ball_facet.friction=1e6"), ["ball_facet.friction", "1e6", "[0, 100]"]),
        ("Young's modulus 1e20 Pa", "dem-simple-shear",
         SMALL + s("ball_ball.law=hertz-mindlin") + s("ball_ball.youngs_modulus=1e20"), ["ball_ball.youngs_modulus"]),
        ("negative vertical stress", "dem-simple-shear", SMALL + s("consolidation.vertical_stress=-2e5"),
         ["consolidation.vertical_stress", "-2"]),
        ("NaN porosity", "dem-simple-shear", SMALL + s("specimen.porosity=nan"), ["specimen.porosity", "nan"]),
        ("a value of 100 KB", "dem-simple-shear", SMALL + s("specimen.porosity=" + "9" * 100000),
         ["specimen.porosity"]),
        ("binary in a value", "dem-simple-shear", SMALL + s("specimen.porosity=0.4\x01\x7f"), ["specimen.porosity"]),
        # Keys that do not apply.
        ("an unknown key", "dem-simple-shear", SMALL + s("shear.target_strian=0.1"), ["shear.target_strian", "target_strain"]),
        ("a key of a law not chosen", "dem-simple-shear", SMALL + s("ball_ball.youngs_modulus=7e10"),
         ["ball_ball.youngs_modulus", "rrlinear"]),
        ("the user's E* with another law than the preset's", "dem-simple-shear",
         ["--preset", "2D"] + s("ball_ball.law=hertz-mindlin") + s("ball_ball.effective_modulus=3e7"),
         ["ball_ball.effective_modulus", "3e+07", "hertz-mindlin"]),
        ("an unknown rolling model", "dem-simple-shear", SMALL + s("ball_ball.law=hertz-mindlin") + s("ball_ball.rolling=bogus"),
         ["ball_ball.rolling", "bogus", "cdt"]),
        ("an unknown law", "dem-simple-shear", SMALL + s("ball_ball.law=jkr-ish"), ["ball_ball.law", "jkr-ish", "hertz-mindlin"]),
        ("an unknown element test", "dem-element-test", ["--preset", "4D"] + s("element.test=uniaxial"),
         ["element.test", "uniaxial"]),
        ("cementation when never", "dem-element-test", ["--preset", "4D"] + s("cementation.after=sometimes"),
         ["cementation.after", "sometimes"]),
        # Restart files used by the wrong test.
        ("consolidate a sheared specimen", "dem-consolidate", SMALL + ["--from", files["final.restart"]], ["stage"]),
        ("cycle a sheared specimen", "dem-cyclic-shear", SMALL + ["--from", files["final.restart"], "--replace"], ["stage = 4"]),
        ("shear a cycled specimen", "dem-simple-shear", SMALL + ["--from", files["cyclic_final.restart"]],
         ["written by dem-cyclic-shear", "consolidated.restart"]),
        ("another diameter than the file's", "dem-simple-shear",
         SMALL + ["--from", files["consolidated.restart"]] + s("specimen.diameter=0.042"),
         ["specimen.diameter = 0.042 here, 0.03 in the file"]),
    ]


def make_files(apps, work):
    """The inputs the cases read: odd files, and restart files of a small run and a cyclic run."""
    files = {"fifo": os.path.join(work, "pipe"), "notes": write(os.path.join(work, "notes.txt"), b"not a restart\n")}
    os.mkfifo(files["fifo"])
    files["fifo.ini"], files["folder.ini"] = os.path.join(work, "fifo.ini"), os.path.join(work, "folder.ini")
    os.mkfifo(files["fifo.ini"])
    os.mkdir(files["folder.ini"])
    files["nul.ini"] = write(os.path.join(work, "nul.ini"), b"[specimen]\nporosity = 0.4\x00\x00\n")
    files["two_points.csv"] = write(os.path.join(work, "two_points.csv"),
                                    b"shear_strain,shear_stress_kPa,volumetric_strain\n0,0,0\n0.4,120,0.05\n")
    rows = "".join(f"{0.01 * k},{1e3 * (20 + k)},{0.001 * k}\n" for k in range(1, 40))
    files["pa_as_kpa.csv"] = write(os.path.join(work, "pa_as_kpa.csv"),
                                   ("shear_strain,shear_stress_kPa,volumetric_strain\n0,0,0\n" + rows).encode())
    run_dir, cyclic_dir = os.path.join(work, "run"), os.path.join(work, "cyclic")
    for app, args, out in (("dem-simple-shear", SMALL + ["--set", "shear.target_strain=0.01"], run_dir),
                           ("dem-cyclic-shear", SMALL + ["--set", "cyclic.max_cycles=1"], cyclic_dir)):
        result = subprocess.run([os.path.join(apps, app)] + args + ["--out", out], capture_output=True, text=True,
                                timeout=600)
        if result.returncode != 0:
            fail(f"{app} could not make the restart files the cases need: {result.stderr.strip()}")
    files["final.restart"] = os.path.join(run_dir, "final.restart")
    files["consolidated.restart"] = os.path.join(run_dir, "consolidated.restart")
    files["cyclic_final.restart"] = os.path.join(cyclic_dir, "final.restart")
    return files


def main():
    apps, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    files = make_files(apps, work)
    failures = []
    for number, (name, app, args, expected) in enumerate(cases(work, files)):
        out = os.path.join(work, f"out_{number}")
        result = subprocess.run([os.path.join(apps, app)] + args + ["--out", out], capture_output=True, timeout=60)
        message = result.stderr.decode("utf-8", "replace").strip()
        problems = []
        if result.returncode != 2:
            problems.append(f"exit {result.returncode}, expected 2")
        problems += [f"no '{text}'" for text in expected if text not in message]
        if len(result.stderr) > MAX_MESSAGE:
            problems.append(f"a message of {len(result.stderr)} bytes")
        if any(b < 0x20 and b not in (0x0a, 0x09) or b == 0x7f for b in result.stderr):
            problems.append("a control byte in the message")
        if os.path.exists(out):
            problems.append("--out was created")
        print(f"{'ok  ' if not problems else 'FAIL'} {name}: {message[:300]!r}", flush=True)
        if problems:
            failures.append(f"{name} ({app}): {'; '.join(problems)}")
    # Not a bad input: another law than the preset's, its own parameters given; the preset's
    # parameters of its law (the 2D E* 4.4e7) go back to their defaults, not refused as the user's.
    result = subprocess.run([os.path.join(apps, "dem-simple-shear"), "--preset", "2D", "--set", "ball_ball.law=hertz-mindlin",
                             "--set", "ball_ball.youngs_modulus=1.8e9", "--print-config"], capture_output=True, text=True, timeout=60)
    ball_ball = result.stdout.split("[ball_ball]")[-1].split("[ball_facet]")[0]
    if result.returncode != 0 or "youngs_modulus = 1.8e+09" not in ball_ball or "effective_modulus = 1.2e+07" not in ball_ball:
        failures.append(f"another law than the 2D preset's: exit {result.returncode}, {result.stderr.strip()[:300]!r}")
    if failures:
        fail(f"{len(failures)} case(s):\n  " + "\n  ".join(failures))
    print(f"all {len(cases(work, files))} bad inputs refused at the door, each naming what was wrong", flush=True)


if __name__ == "__main__":
    main()
