"""What the figure and table scripts of dem-simple-shear runs share (scripts/plot, plot_tables.py):
a run folder's CSV files as tables, the error that skips one output, and the notes they print."""
import csv
import math
import re
import sys
from pathlib import Path

import numpy as np

FIRST_SHEAR_STAGE = 2           # history 'stage': 2 = consolidated, 3 = shearing (ShearStage)


class DataError(Exception):
    """A run's file is missing or unusable: the figures that need it are skipped, not the run."""


def note(message):
    """Report a skipped figure or a missing file without stopping."""
    print(f"plot: note: {message}", file=sys.stderr)


def attempt(what, job):
    """Run one figure or table job; a data problem skips only that output, with a note."""
    try:
        job()
    except DataError as e:
        note(f"{what} skipped: {e}")


class Table:
    """A CSV file held as text columns, so label columns stay text and numbers parse on request."""

    def __init__(self, path):
        self.path = Path(path)
        try:
            with open(self.path, newline="") as f:
                lines = [line for line in f if line.strip() and not line.lstrip().startswith("#")]
        except OSError as e:
            raise DataError(f"cannot read {self.path}: {e.strerror}") from e
        rows = list(csv.reader(lines))
        if not rows:
            raise DataError(f"{self.path} is empty")
        self.names = [name.strip() for name in rows[0]]
        body = [r for r in rows[1:] if len(r) == len(self.names)]
        if len(body) != len(rows) - 1:
            raise DataError(f"{self.path}: rows with a different number of cells than the header")
        self.columns = {name: [r[i].strip() for r in body] for i, name in enumerate(self.names)}

    def __len__(self):
        return len(next(iter(self.columns.values()), []))

    def has(self, *names):
        return all(n in self.columns for n in names)

    def require(self, *names):
        missing = [n for n in names if n not in self.columns]
        if missing:
            raise DataError(f"{self.path} has no column {', '.join(missing)}")

    def text(self, name):
        self.require(name)
        return self.columns[name]

    def number(self, name):
        """Column as floats; an empty cell is NaN, any other non-number is a DataError."""
        values = []
        for cell in self.text(name):
            try:
                values.append(float(cell) if cell else math.nan)
            except ValueError:
                raise DataError(f"{self.path}: column {name} holds '{cell}', not a number") from None
        return np.array(values, dtype=float)

    def subset(self, mask):
        """The rows where mask is true, as a new Table sharing the file name."""
        part = object.__new__(Table)
        part.path, part.names = self.path, self.names
        part.columns = {n: [v for v, keep in zip(col, mask) if keep] for n, col in self.columns.items()}
        return part


class Run:
    """One dem-simple-shear output folder: its name and whichever of its files could be read."""

    def __init__(self, path, name):
        self.path = Path(path)
        self.name = name
        self.file_name = re.sub(r"[^A-Za-z0-9_.-]", "_", name)
        if not (self.path / "history.csv").exists() and (self.path / "ensemble.csv").exists():
            # A scripts/ensemble folder: its seeds' mean as the curve, their range as a band.
            self.history = self._optional("ensemble.csv", lambda p: shear_history(ensemble_table(Table(p))))
        else:
            self.history = self._optional("history.csv", lambda p: shear_history(Table(p)))
        self.fabric = self._optional("fabric.csv", Table)
        self.snapshots = self._optional("snapshots", snapshot_index)

    def _optional(self, name, load):
        """load(path) of a file in the run, or None: silently when it is absent (the figures that
        need it say so), with a note when it exists but cannot be used."""
        path = self.path / name
        if not path.exists():
            return None
        try:
            return load(path)
        except DataError as e:
            note(f"{self.name}: {e}")
            return None


def shear_history(table):
    """History rows from consolidation onwards: earlier stages (generation) have no shear strain yet."""
    table.require("shear_strain")
    if table.has("stage"):
        table = table.subset(table.number("stage") >= FIRST_SHEAR_STAGE)
    if len(table) == 0:
        raise DataError(f"{table.path} has no rows from consolidation onwards")
    return table


def ensemble_table(table):
    """An ensemble.csv (c_mean, c_std, c_min, c_max per history column c) with each c_mean also
    under the plain name c, so that it draws as a run; c_min and c_max draw its band."""
    for name in list(table.names):
        if name.endswith("_mean"):
            table.columns[name[:-len("_mean")]] = table.columns[name]
            table.names.append(name[:-len("_mean")])
    return table


def snapshot_index(folder):
    """(label, shear strain) of each snapshot in time order, from snapshots.csv or the file names."""
    if not folder.is_dir():
        raise DataError(f"no snapshots folder {folder}")
    index_file = folder / "snapshots.csv"
    if index_file.is_file():
        index = Table(index_file)
        return list(zip(index.text("label"), index.number("shear_strain")))
    labels = sorted(p.name[len("contacts_"):-4] for p in folder.glob("contacts_*.csv"))
    labels += sorted(p.name[len("balls_"):-4] for p in folder.glob("balls_*.csv")
                     if p.name[len("balls_"):-4] not in labels)
    if not labels:
        raise DataError(f"{folder} has no snapshot CSV files")
    return [(label, strain_of_label(label)) for label in sorted(labels)]


def strain_of_label(label):
    """Shear strain from a label such as strain_20.0 (percent), NaN for other labels."""
    match = re.fullmatch(r"strain_(\d+(?:\.\d+)?)", label)
    return float(match.group(1)) / 100.0 if match else math.nan


def percent_text(strain):
    return "?" if not np.isfinite(strain) else f"{100.0 * strain:.1f} %"
