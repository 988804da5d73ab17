#!/usr/bin/python3
"""scripts/cyclic-campaign and scripts/plot-cyclic on the reduced specimen (30 mm x 12 mm, 4D balls):
a campaign of two CSRs x one seed for three cycles at constant volume, then the figures of its runs.

Checked: campaign.csv has one row per run, each stopped by the cycle count at N = 3 (the limits are
set out of reach); the run at the larger CSR ends with the larger r_u (a larger cyclic stress
contracts the specimen more: the ordering CSR-N curves rest on); both runs of the seed start from
the same consolidated state (the same sigma_v0 in their summaries); the figures exist with the sizes
their fixed inches and dpi give.

Usage: check_cyclic_scripts.py SOURCE_DIR BUILD_DIR
"""

import json
import os
import struct
import subprocess
import sys
import tempfile
from pathlib import Path


def png_size(path):
    with open(path, "rb") as f:
        head = f.read(24)
    assert head[:8] == b"\x89PNG\r\n\x1a\n", f"{path}: not a PNG"
    return struct.unpack(">II", head[16:24])


def main():
    source, build = Path(sys.argv[1]), Path(sys.argv[2])
    env = dict(os.environ, LIBDEM_BUILD_DIR=str(build.resolve()))
    with tempfile.TemporaryDirectory(prefix="libdem_cyclic_") as tmp:
        out = Path(tmp) / "campaign"
        subprocess.run([sys.executable, str(source / "scripts" / "cyclic-campaign"), "--csr", "0.05,0.15", "--seeds", "1",
                        "--jobs", "2", "--out", str(out), "--", "--preset", "4D", "--set", "specimen.diameter=0.03",
                        "--set", "specimen.height=0.012", "--set", "cyclic.max_cycles=3", "--set", "cyclic.ru_limit=0",
                        "--set", "cyclic.da_strain_limit=0"], check=True, env=env)
        lines = (out / "campaign.csv").read_text().split("\n")
        assert lines[0] == "csr,seed,n_l_pore_pressure,n_l_strain,stop,cycles", lines[0]
        rows = [line.split(",") for line in lines[1:] if line]
        assert len(rows) == 2, rows
        for r in rows:
            assert r[4] == "cycles" and float(r[5]) == 3.0, r
        ru_end, sigma_v0 = {}, set()
        for csr in ("0.05", "0.15"):
            run = out / f"csr_{csr}" / "seed_1"
            summary = json.loads((run / "summary.json").read_text())
            ru_end[csr] = summary["final"]["pore_pressure_ratio"]
            sigma_v0.add(summary["vertical_stress_initial_Pa"])
        assert ru_end["0.15"] > ru_end["0.05"], ru_end
        assert len(sigma_v0) == 1, sigma_v0
        assert png_size(out / "csr_n.png") == (960, 720)
        figures = Path(tmp) / "figures"
        subprocess.run([sys.executable, str(source / "scripts" / "plot-cyclic"), str(out / "csr_0.05" / "seed_1"),
                        str(out / "csr_0.15" / "seed_1"), "--out", str(figures)], check=True)
        assert png_size(figures / "loops.png") == (960, 720)
        assert png_size(figures / "stress_path.png") == (1650, 720)
        assert png_size(figures / "pore_pressure.png") == (960, 720)
    print("cyclic scripts: campaign and figures as expected")


if __name__ == "__main__":
    main()
