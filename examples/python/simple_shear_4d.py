#!/usr/bin/python3
"""The study's 4D simple-shear test from Python (dem-simple-shear --preset 4D), then the peak and
the curve read back as NumPy arrays. Every key of `dem-simple-shear --print-config` can be given,
nested by section as below or flat ("shear.target_strain": 0.4).

Run: PYTHONPATH=build/python /usr/bin/python3 examples/python/simple_shear_4d.py [out] [target strain]
"""

import sys

import numpy as np

import libdem

out = sys.argv[1] if len(sys.argv) > 1 else "runs/python-4D"
strain = float(sys.argv[2]) if len(sys.argv) > 2 else 0.4
test = libdem.SimpleShear({"shear": {"target_strain": strain}, "engine": {"threads": 2}}, out=out, preset="4D")
test.open_outputs(replace=True)
test.run()            # generation, consolidation to 200 kPa, shear (progress on stdout)
test.write_summary()

h = test.history()
ratio = h["shear_stress"] / h["vertical_stress"]
peak = int(np.argmax(ratio))
print(f"{test.ball_count} balls, H_c = {test.consolidated_height * 1e3:.2f} mm")
print(f"peak tau/sigma_v = {ratio[peak]:.3f} at {100 * h['shear_strain'][peak]:.1f} % strain, "
      f"volumetric strain there {100 * h['volumetric_strain'][peak]:.2f} %")
print(f"at {100 * h['shear_strain'][-1]:.1f} %: tau/sigma_v = {ratio[-1]:.3f}, "
      f"principal stress rotation {h['principal_rotation_deg'][-1]:.1f} deg")
