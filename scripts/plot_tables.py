"""The study's tables from dem-simple-shear runs (scripts/plot writes them): Table 4 (contact number
and mean contact force after consolidation and at the last state) and Tables 2-3 (relative
differences of the curves from a reference, the lab curve or the first run), as CSV and Markdown."""
import csv
import math

import numpy as np

from plot_support import DataError, note


def fabric_states(fabric):
    """The x-z rows of fabric.csv grouped by label, in file order, each sorted by bin."""
    fabric.require("label", "shear_strain", "plane", "bin_lo_deg", "bin_hi_deg", "contact_count",
                   "mean_normal_force_N")
    xz = fabric.subset([p == "xz" for p in fabric.text("plane")])
    states = {}
    for label in dict.fromkeys(xz.text("label")):
        rows = xz.subset([lab == label for lab in xz.text("label")])
        order = np.argsort(rows.number("bin_lo_deg"))
        states[label] = {name: rows.number(name)[order] for name in rows.names
                         if name not in ("label", "plane")}
    if not states:
        raise DataError(f"{fabric.path} has no x-z plane rows")
    return states


def contact_state_from_fabric(fabric):
    """(label, strain, contacts, mean force) after consolidation and at the last fabric state."""
    states = fabric_states(fabric)
    strains = {label: s["shear_strain"][0] for label, s in states.items()}
    first = min(strains, key=strains.get)
    last = max(reversed(list(strains)), key=strains.get)
    return [fabric_totals(label, states[label]) for label in (first, last)]


def fabric_totals(label, state):
    """Total contacts and mean normal force of one state: the logged totals, else the x-z bins."""
    count = state["contact_count"]
    if "contacts_total" in state and "mean_force_all_N" in state:
        return label, state["shear_strain"][0], state["contacts_total"][0], state["mean_force_all_N"][0]
    force = np.nan_to_num(state["mean_normal_force_N"], nan=0.0)
    total = count.sum()
    return label, state["shear_strain"][0], total, (count * force).sum() / total if total else math.nan


def contact_state_from_history(history):
    """The same pair from the first and last history rows, for runs without fabric.csv."""
    history.require("contacts", "mean_contact_force")
    strain, contacts, force = (history.number(c) for c in ("shear_strain", "contacts", "mean_contact_force"))
    return [("history first row", strain[0], contacts[0], force[0]),
            ("history last row", strain[-1], contacts[-1], force[-1])]


def change_percent(before, after):
    return 100.0 * (after - before) / before if before else math.nan


def contact_rows(runs):
    """Table 4 of the study, one row per run."""
    rows = []
    for run in runs:
        try:
            if run.fabric is not None:
                states, source = contact_state_from_fabric(run.fabric), "fabric.csv"
            elif run.history is not None:
                states, source = contact_state_from_history(run.history), "history.csv"
            else:
                raise DataError("neither fabric.csv nor history.csv")
        except DataError as e:
            note(f"{run.name}: not in table_contacts: {e}")
            continue
        (l0, s0, n0, f0), (l1, s1, n1, f1) = states
        n0, n1 = (int(n) if np.isfinite(n) else n for n in (n0, n1))
        rows.append({"run": run.name, "source": source,
                     "consolidation_label": l0, "consolidation_shear_strain": s0,
                     "consolidation_contacts": n0, "consolidation_mean_force_N": f0,
                     "last_label": l1, "last_shear_strain": s1, "last_contacts": n1, "last_mean_force_N": f1,
                     "contacts_change_percent": change_percent(n0, n1),
                     "mean_force_change_percent": change_percent(f0, f1)})
    return rows


def reference_points(reference, column, eps):
    """(strain, value, usable) of the reference curve; usable drops missing and near-zero values."""
    strain, value = reference.number("shear_strain"), reference.number(column)
    usable = np.isfinite(strain) & np.isfinite(value) & (np.abs(value) >= eps)
    return strain, value, usable


def interpolate_run(history, column, strain):
    """The run's column at the given strains (linear), NaN outside the run's strain range."""
    x, y = history.number("shear_strain"), history.number(column)
    ok = np.isfinite(x) & np.isfinite(y)
    x, y = x[ok], y[ok]
    order = np.argsort(x, kind="stable")
    x, y = x[order], y[order]
    first = np.concatenate([[True], np.diff(x) > 0])
    x, y = x[first], y[first]
    if len(x) == 0:
        return np.full(strain.shape, math.nan)
    return np.interp(strain, x, y, left=math.nan, right=math.nan)


def relative_difference(reference, history, column, eps):
    """max and mean of |ref - run| / |ref| (%) of one quantity on the reference's strain points."""
    strain, ref, usable = reference_points(reference, column, eps)
    model = interpolate_run(history, column, strain)
    compared = usable & np.isfinite(model)
    rd = 100.0 * np.abs(ref[compared] - model[compared]) / np.abs(ref[compared])
    return {"max_relative_difference_percent": rd.max() if rd.size else math.nan,
            "mean_relative_difference_percent": rd.mean() if rd.size else math.nan,
            "points_compared": int(compared.sum()), "points_skipped": int((~usable).sum()),
            "points_out_of_range": int((usable & ~np.isfinite(model)).sum()), "threshold": eps}


def relative_difference_rows(reference_name, reference, runs, eps_stress, eps_strain):
    """Tables 2-3: one row per run and quantity that both the run and the reference have."""
    quantities = [("shear_stress", eps_stress), ("volumetric_strain", eps_strain),
                  ("sigma_1", eps_stress), ("sigma_2", eps_stress), ("sigma_3", eps_stress)]
    rows = []
    for run in runs:
        for column, eps in quantities:
            if run.history is None or not (reference.has(column) and run.history.has(column)):
                continue
            try:
                stats = relative_difference(reference, run.history, column, eps)
            except DataError as e:
                note(f"{run.name}: {column} not in table_relative_difference: {e}")
                continue
            rows.append({"run": run.name, "reference": reference_name, "quantity": column, **stats})
    return rows


def write_csv(path, rows, written):
    """Full-precision CSV, so other tools (and the tests) can recompute the numbers."""
    with open(path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(rows[0]))
        writer.writeheader()
        for row in rows:
            writer.writerow({k: repr(float(v)) if isinstance(v, (float, np.floating)) else v
                             for k, v in row.items()})
    written.append(path)


def markdown_cell(value):
    if isinstance(value, (float, np.floating)):
        if not np.isfinite(value):
            return "n/a"
        return f"{value:.0f}" if float(value).is_integer() and abs(value) >= 1 else f"{value:.4g}"
    return str(value)


def write_markdown(path, title, columns, rows, footnote, written):
    """A Markdown table of selected columns (header text, row key), for reports."""
    lines = [f"# {title}", "", "| " + " | ".join(h for h, _ in columns) + " |",
             "|" + "---|" * len(columns)]
    lines += ["| " + " | ".join(markdown_cell(row[key]) for _, key in columns) + " |" for row in rows]
    lines += ["", footnote, ""]
    path.write_text("\n".join(lines))
    written.append(path)


def write_tables(runs, lab, args, out, written):
    """table_contacts always; table_relative_difference with a lab curve or several runs."""
    rows = contact_rows(runs)
    if rows:
        write_csv(out / "table_contacts.csv", rows, written)
        write_markdown(out / "table_contacts.md", "Contact number and average contact force (study Table 4)",
                       [("run", "run"), ("first state", "consolidation_label"),
                        ("contacts, first", "consolidation_contacts"),
                        ("mean force, first (N)", "consolidation_mean_force_N"), ("last state", "last_label"),
                        ("contacts, last", "last_contacts"), ("mean force, last (N)", "last_mean_force_N"),
                        ("contacts change (%)", "contacts_change_percent"),
                        ("force change (%)", "mean_force_change_percent")],
                       rows, "First state: after consolidation. Ball-ball contacts with a compressive normal force; "
                             "mean of their normal force. Source: fabric.csv totals, or the first and last "
                             "history rows for runs without fabric.csv.", written)
    if lab is not None:
        reference_name, reference, compared = lab.name, lab.table, runs
    elif len(runs) > 1 and runs[0].history is not None:
        reference_name, reference, compared = runs[0].name, runs[0].history, runs[1:]
    else:
        if len(runs) > 1:
            note(f"{runs[0].name} (the reference) has no history; table_relative_difference skipped")
        return
    rows = relative_difference_rows(reference_name, reference, compared, args.eps_stress, args.eps_strain)
    if not rows:
        note("no quantity shared by the reference and the runs; table_relative_difference skipped")
        return
    write_csv(out / "table_relative_difference.csv", rows, written)
    write_markdown(out / "table_relative_difference.md",
                   f"Relative difference from {reference_name} (study Tables 2-3)",
                   [("run", "run"), ("quantity", "quantity"), ("max (%)", "max_relative_difference_percent"),
                    ("mean (%)", "mean_relative_difference_percent"), ("points", "points_compared"),
                    ("skipped", "points_skipped"), ("out of range", "points_out_of_range")],
                   rows, f"Relative difference |ref - run| / |ref|, each run interpolated linearly onto the "
                         f"strain points of {reference_name}; skipped: |ref| < {args.eps_stress:g} Pa (stresses) or "
                         f"< {args.eps_strain:g} (volumetric strain).", written)
