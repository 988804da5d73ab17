#!/usr/bin/python3
"""CTest plot_figures: scripts/plot on small synthetic runs whose answers are known by hand.

Usage: check_plots.py SOURCE_DIR

Why synthetic runs: a real dem-simple-shear run takes minutes and its numbers are not known in
advance. Here every input is written by this file, so the figure list, the PNG sizes (figure size
in inches x 150 dpi), Table 4 (contact totals) and Tables 2-3 (relative differences of a run that
is the reference scaled by 1.1, i.e. 10 % everywhere) can be checked exactly. A second run has
no fabric.csv and no snapshots, to check that missing files skip figures instead of failing.
"""

import csv
import math
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.image  # noqa: E402

DPI = 150
CURVE_PX = (960, 720)      # 6.4 x 4.8 in
SECTION_PX = (1200, 600)   # 8.0 x 4.0 in
ROSE_PX = (900, 900)       # 6.0 x 6.0 in
ROSE_PANEL_PX = (1800, 480)  # 12.0 x 3.2 in: one row, the one run with a fabric
SCALE = 1.1                # run B = 1.1 x run A, so B differs from A by 10 %
SCALED = ("shear_stress", "volumetric_strain", "sigma_1", "sigma_2", "sigma_3")
SNAPSHOTS = (("strain_00.0", 0.0), ("strain_20.0", 0.2), ("strain_40.0", 0.4))
FABRIC_STATES = (("strain_00.0", 0.0), ("strain_40.0", 0.4))


class Checks:
    """Counts passed and failed checks and keeps the failure messages for the summary."""

    def __init__(self):
        self.passed, self.failures = 0, []

    def check(self, ok, what):
        if ok:
            self.passed += 1
        else:
            self.failures.append(what)
            print(f"FAIL: {what}")
        return ok

    def close(self, what, got, want, tol=1e-9):
        ok = got is not None and math.isclose(float(got), float(want), rel_tol=tol, abs_tol=tol)
        return self.check(ok, f"{what}: got {got}, want {want}")


# ---------------------------------------------------------------- synthetic inputs

def write_csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        writer = csv.writer(f)
        writer.writerow(header)
        writer.writerows([[repr(float(v)) if isinstance(v, float) else v for v in row] for row in rows])


def history_columns():
    """A known curve: a generation row (stage 1, to be ignored), then consolidation and shear to 40 %."""
    s = np.linspace(0.0, 0.4, 41)
    cols = {
        "time": 0.1 + s,
        "stage": np.where(s == 0, 2.0, 3.0),
        "shear_strain": s,
        "shear_stress": 150e3 * np.tanh(s / 0.03),
        "vertical_stress": np.full(s.shape, 200e3),
        "volumetric_strain": 0.05 * s * (1 - s / 0.5),
        "sigma_1": 200e3 + 300e3 * s,
        "sigma_2": 120e3 - 50e3 * s,
        "sigma_3": 110e3 - 150e3 * s,
        "principal_rotation_deg": 45 * (1 - np.exp(-s / 0.03)),
        "contacts": 1000 + 500 * s,
        "mean_contact_force": 1.5 + s,
        "coordination_number": 5 + s,
        "porosity": 0.35 + 0.01 * s,
    }
    generation = {k: 0.0 for k in cols}
    generation["stage"] = 1.0
    return {k: np.concatenate([[generation[k]], v]) for k, v in cols.items()}


def write_history(run, cols):
    names = list(cols)
    write_csv(run / "history.csv", names, [[float(cols[n][i]) for n in names] for i in range(len(cols["time"]))])


def fabric_bins(state):
    """Counts and mean forces of the 18 x-z bins of one state; one bin empty (force NaN)."""
    m = np.arange(18)
    if state == 0:
        counts = 10.0 + m
    else:
        counts = 20.0 + 2 * ((7 * m) % 18)
    counts[5] = 0
    forces = 1.0 + 0.1 * m + state
    forces[5] = math.nan
    return counts, forces


def fabric_totals(state):
    """What table_contacts must report: total contacts and their mean normal force."""
    counts, forces = fabric_bins(state)
    total = counts.sum()
    return total, np.nansum(counts * forces) / total


def write_fabric(run):
    header = ["label", "shear_strain", "plane", "bin_lo_deg", "bin_hi_deg", "contact_count", "contact_fraction",
              "mean_normal_force_N", "a", "theta_a_deg", "f0_N", "a_n", "theta_n_deg", "a_direct",
              "theta_a_direct_deg", "contacts_total", "mean_force_all_N"]
    rows = []
    for state, (label, strain) in enumerate(FABRIC_STATES):
        counts, forces = fabric_bins(state)
        total, mean = fabric_totals(state)
        for plane in ("xz", "xy"):
            for m in range(18):
                f = "nan" if math.isnan(forces[m]) else repr(float(forces[m]))
                rows.append([label, strain, plane, float(10 * m), float(10 * m + 10), int(counts[m]),
                             counts[m] / total, f, 0.2, 90.0 - 45 * state, 1.5, 0.3, 90.0 - 40 * state, 0.2,
                             90.0, int(total), mean])
    write_csv(run / "fabric.csv", header, rows)


def ball_grid():
    """Ball centres (m): some inside the slabs |y| < 2 mm and |x| < 2 mm, some outside both."""
    return [(x, y, z) for x in np.linspace(-0.03, 0.03, 7) for y in (-0.001, 0.001, 0.01)
            for z in (0.003, 0.011, 0.019)]


def write_snapshots(run):
    folder = run / "snapshots"
    balls = ball_grid()
    write_csv(folder / "snapshots.csv", ["label", "time_s", "shear_strain", "balls", "contacts"],
              [[label, 0.1 + s, s, len(balls), 0] for label, s in SNAPSHOTS])
    for k, (label, strain) in enumerate(SNAPSHOTS):
        ball_rows = []
        for i, (x, y, z) in enumerate(balls):
            u = (0.0, 0.0, 0.0) if k == 0 else (-0.004 * (1 - z / 0.022), 0.0002 * math.sin(i), -0.0003 * z / 0.022)
            ball_rows.append([i, x, y, z, 0.0015, *u, 0.0, 0.0, 0.0])
        write_csv(folder / f"balls_{label}.csv",
                  ["id", "x", "y", "z", "radius", "ux", "uy", "uz", "vx", "vy", "vz"], ball_rows)
        contact_rows = []
        for a in balls:
            for b in balls:
                if a < b and math.dist(a, b) < 0.0105 and a[1] == b[1]:
                    c = [(p + q) / 2 for p, q in zip(a, b)]
                    fn = 0.1 + 100 * abs(a[2] - b[2]) + 0.1 * k   # N: vertical contacts carry more
                    contact_rows.append([*a, *b, *c, fn, fn, 0.0, 0.0])
        write_csv(folder / f"contacts_{label}.csv",
                  ["x1", "y1", "z1", "x2", "y2", "z2", "cx", "cy", "cz", "normal_force", "force_x", "force_y",
                   "force_z"], contact_rows)


def make_inputs(root):
    """Run A (everything), run B (A's history scaled by 1.1, nothing else) and two lab curves."""
    cols = history_columns()
    run_a, run_b = root / "runA", root / "runB"
    write_history(run_a, cols)
    write_fabric(run_a)
    write_snapshots(run_a)
    write_history(run_b, {k: v * SCALE if k in SCALED else v for k, v in cols.items()})
    shear = cols["stage"] >= 2
    lab_rows = [[float(cols[n][i]) for n in ("shear_strain",) + SCALED] for i in np.flatnonzero(shear)[::2]]
    lab_rows.append([0.5, 160e3, 0.01, 350e3, 100e3, 50e3])   # beyond the runs' 40 %: out of range
    write_csv(root / "lab.csv", ("shear_strain",) + SCALED, lab_rows)
    with open(root / "lab.csv") as f:
        text = f.read()
    (root / "lab.csv").write_text("# synthetic lab curve, SI units\n" + text)
    mid = np.linspace(0.005, 0.395, 40)
    write_csv(root / "lab_mid.csv", ["shear_strain", "shear_stress"],
              [[float(s), float(150e3 * np.tanh(s / 0.03))] for s in mid])
    return run_a, run_b, cols


# ---------------------------------------------------------------- running and reading outputs

def run_plot(source, args, tmp):
    """scripts/plot with this interpreter (the one that has matplotlib), capturing its output."""
    env = dict(os.environ, MPLCONFIGDIR=str(tmp / "mplconfig"))
    return subprocess.run([sys.executable, str(source / "scripts" / "plot"), *map(str, args)],
                          capture_output=True, text=True, env=env, timeout=600)


def png_size(path):
    """(width, height) from the IHDR chunk, or None if the file is not a PNG."""
    data = path.read_bytes()[:24]
    if len(data) < 24 or data[:8] != b"\x89PNG\r\n\x1a\n" or data[12:16] != b"IHDR":
        return None
    return struct.unpack(">II", data[16:24])


def check_png(checks, path, size):
    if not checks.check(path.is_file(), f"{path.name} exists"):
        return
    checks.check(png_size(path) == size, f"{path.name} is a PNG of {size[0]}x{size[1]} px (got {png_size(path)})")
    pixels = matplotlib.image.imread(str(path))
    checks.check(float(np.var(pixels)) > 0, f"{path.name} is not blank")


def read_rows(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def expected_pngs(run_part, several_labels=False):
    """Figure names and pixel sizes for run A's inputs; run_part is '' or 'A_' when several runs."""
    figures = {name: CURVE_PX for name in ("shear_stress.png", "volumetric_strain.png", "principal_stresses.png",
                                           "principal_rotation.png")}
    for k, (label, _) in enumerate(SNAPSHOTS):
        figures[f"force_network_{run_part}{label}.png"] = SECTION_PX
        if k > 0:
            figures[f"displacement_front_{run_part}{label}.png"] = SECTION_PX
            figures[f"displacement_side_{run_part}{label}.png"] = SECTION_PX
    for label, _ in FABRIC_STATES:
        figures[f"rose_force_{run_part}{label}.png"] = ROSE_PX
        figures[f"rose_number_{run_part}{label}.png"] = ROSE_PX
    figures["roses.png"] = ROSE_PANEL_PX
    return figures


# ---------------------------------------------------------------- the checks

def check_figures(checks, out, figures):
    for name, size in figures.items():
        check_png(checks, out / name, size)
    extra = {p.name for p in out.glob("*.png")} - set(figures)
    checks.check(not extra, f"no unexpected figures in {out.name} (got {sorted(extra)})")


def check_contact_table(checks, out, cols):
    """Table 4: run A from the fabric totals, run B from its first and last shear-history rows."""
    rows = {r["run"]: r for r in read_rows(out / "table_contacts.csv")}
    checks.check(set(rows) == {"A", "B"}, f"table_contacts has runs A and B (got {sorted(rows)})")
    (n0, f0), (n1, f1) = fabric_totals(0), fabric_totals(1)
    a = rows.get("A", {})
    checks.close("A contacts after consolidation", a.get("consolidation_contacts"), n0)
    checks.close("A mean force after consolidation (N)", a.get("consolidation_mean_force_N"), f0)
    checks.close("A contacts at the last fabric state", a.get("last_contacts"), n1)
    checks.close("A mean force at the last fabric state (N)", a.get("last_mean_force_N"), f1)
    checks.close("A contact change (%)", a.get("contacts_change_percent"), 100 * (n1 - n0) / n0)
    checks.check(a.get("last_label") == FABRIC_STATES[-1][0], "A last state is the last fabric label")
    b = rows.get("B", {})
    shear = cols["stage"] >= 2   # the generation row must not count as 'after consolidation'
    checks.close("B contacts after consolidation", b.get("consolidation_contacts"), cols["contacts"][shear][0])
    checks.close("B mean force at the end (N)", b.get("last_mean_force_N"), cols["mean_contact_force"][shear][-1])
    checks.check((out / "table_contacts.md").is_file(), "table_contacts.md exists")


def check_scaled_copy(checks, table, run, ref_cols, ref_rows, eps):
    """Run = 1.1 x reference: 10 % max and mean for every quantity, skipped points counted by hand."""
    rows = {r["quantity"]: r for r in read_rows(table) if r["run"] == run}
    checks.check(set(rows) == set(SCALED), f"{table.name}: quantities for {run} (got {sorted(rows)})")
    for quantity in SCALED:
        row = rows.get(quantity, {})
        ref = ref_cols[quantity][ref_rows]
        limit = eps["volumetric_strain" if quantity == "volumetric_strain" else "stress"]
        in_range = ref_cols["shear_strain"][ref_rows] <= 0.4
        usable = np.abs(ref) >= limit
        checks.close(f"{table.name} {run} {quantity} max (%)", row.get("max_relative_difference_percent"), 10.0)
        checks.close(f"{table.name} {run} {quantity} mean (%)", row.get("mean_relative_difference_percent"), 10.0)
        checks.close(f"{table.name} {run} {quantity} points compared", row.get("points_compared"),
                     int((usable & in_range).sum()))
        checks.close(f"{table.name} {run} {quantity} points skipped", row.get("points_skipped"),
                     int((~usable).sum()))


def check_interpolation(checks, table, cols):
    """Lab points halfway between run points: the run is the mean of its two neighbours there."""
    shear = cols["stage"] >= 2
    s, tau_b = cols["shear_strain"][shear], SCALE * cols["shear_stress"][shear]
    mid = np.linspace(0.005, 0.395, 40)
    lab = 150e3 * np.tanh(mid / 0.03)
    model = (tau_b[:-1] + tau_b[1:]) / 2
    checks.check(np.allclose((s[:-1] + s[1:]) / 2, mid), "midpoints of the synthetic run")
    rd = 100 * np.abs(lab - model) / lab
    row = {r["quantity"]: r for r in read_rows(table)}.get("shear_stress", {})
    checks.close("interpolated max relative difference (%)", row.get("max_relative_difference_percent"),
                 rd.max(), 1e-7)
    checks.close("interpolated mean relative difference (%)", row.get("mean_relative_difference_percent"),
                 rd.mean(), 1e-7)


def check_bad_arguments(checks, source, tmp, run_a):
    """Each wrong invocation exits 2 with a message and draws nothing."""
    bad_lab = tmp / "bad_lab.csv"
    bad_lab.write_text("shear_strain,tau\n0,0\n")
    empty = tmp / "empty_run"
    empty.mkdir()
    cases = {
        "missing run folder": [tmp / "no_such_run", "--out", tmp / "bad1"],
        "missing --out": [run_a],
        "--labels count": [run_a, "--out", tmp / "bad2", "--labels", "A,B"],
        "lab without shear_stress": [run_a, "--out", tmp / "bad3", "--lab", bad_lab],
        "missing lab file": [run_a, "--out", tmp / "bad4", "--lab", tmp / "no_such.csv"],
        "folder that is not a run": [empty, "--out", tmp / "bad5"],
        "negative --eps-stress": [run_a, "--out", tmp / "bad6", "--eps-stress", "-1"],
    }
    for what, args in cases.items():
        result = run_plot(source, args, tmp)
        checks.check(result.returncode == 2 and result.stderr.strip(),
                     f"{what}: exit 2 with a message (got {result.returncode}: {result.stderr.strip()[-200:]})")


def check_ran(checks, result, what):
    ok = checks.check(result.returncode == 0, f"{what}: exit 0 (got {result.returncode}):\n{result.stderr}")
    checks.check("figures" in result.stdout, f"{what}: prints where the figures are")
    return ok


def main(argv):
    if len(argv) != 2:
        print("usage: check_plots.py SOURCE_DIR", file=sys.stderr)
        return 2
    source = Path(argv[1]).resolve()
    checks = Checks()
    plot = source / "scripts" / "plot"
    checks.check(plot.is_file() and os.access(plot, os.X_OK), "scripts/plot exists and is executable")
    with tempfile.TemporaryDirectory(prefix="libdem_plot_") as name:
        tmp = Path(name)
        run_a, run_b, cols = make_inputs(tmp)
        eps = {"stress": 1000.0, "volumetric_strain": 1e-4}
        shear = cols["stage"] >= 2

        single = run_plot(source, [run_a, "--out", tmp / "figs_single"], tmp)
        if check_ran(checks, single, "one run"):
            check_figures(checks, tmp / "figs_single", expected_pngs(""))
            checks.check(not (tmp / "figs_single" / "table_relative_difference.csv").exists(),
                         "one run without --lab: no relative-difference table")

        two = run_plot(source, [run_a, run_b, "--labels", "A,B", "--out", tmp / "figs_two"], tmp)
        if check_ran(checks, two, "two runs"):
            check_figures(checks, tmp / "figs_two", expected_pngs("A_"))
            checks.check("B" in two.stderr and "note" in two.stderr, "run B's missing files are noted")
            check_contact_table(checks, tmp / "figs_two", cols)
            check_scaled_copy(checks, tmp / "figs_two" / "table_relative_difference.csv", "B", cols, shear, eps)
            checks.check((tmp / "figs_two" / "table_relative_difference.md").is_file(),
                         "table_relative_difference.md exists")

        lab = run_plot(source, [run_b, "--lab", tmp / "lab.csv", "--out", tmp / "figs_lab"], tmp)
        if check_ran(checks, lab, "lab curve"):
            lab_cols = {k: np.array([float(r[k]) for r in read_rows_skipping_comments(tmp / "lab.csv")])
                        for k in ("shear_strain",) + SCALED}
            all_rows = np.ones(len(lab_cols["shear_strain"]), dtype=bool)
            check_scaled_copy(checks, tmp / "figs_lab" / "table_relative_difference.csv", "runB", lab_cols,
                              all_rows, eps)
            row = {r["quantity"]: r for r in read_rows(tmp / "figs_lab" / "table_relative_difference.csv")}
            checks.close("lab point beyond the run counted out of range",
                         row.get("shear_stress", {}).get("points_out_of_range"), 1)
            for name in ("shear_stress.png", "volumetric_strain.png", "principal_stresses.png"):
                check_png(checks, tmp / "figs_lab" / name, CURVE_PX)

        mid = run_plot(source, [run_b, "--lab", tmp / "lab_mid.csv", "--out", tmp / "figs_mid"], tmp)
        if check_ran(checks, mid, "lab curve between run points"):
            check_interpolation(checks, tmp / "figs_mid" / "table_relative_difference.csv", cols)

        check_bad_arguments(checks, source, tmp, run_a)

    print(f"{checks.passed} passed, {len(checks.failures)} failed")
    return 1 if checks.failures else 0


def read_rows_skipping_comments(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(line for line in f if not line.startswith("#")))


if __name__ == "__main__":
    sys.exit(main(sys.argv))
