#!/usr/bin/python3
"""What a Python user does with a clone: a virtual environment, `pip install` of the clone (editable,
then regular), then the package used from a folder outside the repository: pour.py runs, help()
explains, and the installed type stubs define every public name. Offline, as the README says: the
environment sees Debian's packages (--system-site-packages) and pip builds without isolation and
without an index. The source tree must not be written (the build folder is WORK/build-pip).

    pip_install_check.py SOURCE_DIR WORK_DIR

WORK_DIR keeps the build folder between runs, so a second run rebuilds only what changed; the
environment is made anew each time. Prints the install times and the stubs' coverage.
"""

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

source, work = Path(sys.argv[1]).resolve(), Path(sys.argv[2]).resolve()


def run(*command, cwd=None, env=None):
    print("$", " ".join(map(str, command)), flush=True)
    done = subprocess.run([str(c) for c in command], cwd=cwd, env=env, text=True, capture_output=True)
    if done.returncode != 0:
        sys.exit(f"failed ({done.returncode}):\n{done.stdout}\n{done.stderr}")
    return done.stdout


def tree(folder):
    """The source tree's entries that a build could write: the top level and python/."""
    return sorted(os.listdir(folder)) + sorted("python/" + name for name in os.listdir(folder / "python"))


venv = work / "venv"
shutil.rmtree(venv, ignore_errors=True)
work.mkdir(parents=True, exist_ok=True)
before = tree(source)
run(sys.executable, "-m", "venv", "--system-site-packages", venv)
python = venv / "bin" / "python"
env = dict(os.environ, LIBDEM_PIP_BUILD_DIR=str(work / "build-pip"), PIP_NO_INPUT="1", PIP_DISABLE_PIP_VERSION_CHECK="1")
outside = Path(tempfile.mkdtemp(prefix="libdem-pip-"))
where = "import libdem; print(libdem.__file__)"

# Editable: the package in the build folder, named by a .pth file.
start = time.monotonic()
run(python, "-m", "pip", "install", "--no-build-isolation", "--no-index", "-e", source, cwd=outside, env=env)
editable = time.monotonic() - start
module = Path(run(python, "-c", where, cwd=outside).strip())
assert module.parent == work / "build-pip" / "python" / "libdem", module

# Regular: the package in the environment's site-packages.
start = time.monotonic()
run(python, "-m", "pip", "install", "--no-build-isolation", "--no-index", source, cwd=outside, env=env)
regular = time.monotonic() - start
module = Path(run(python, "-c", where, cwd=outside).strip())
package = module.parent
assert package.name == "libdem" and package.parent.name == "site-packages" and venv in package.parents, module
assert sorted(p.name for p in package.iterdir()) == sorted([module.name, "__init__.pyi", "py.typed"]), list(package.iterdir())
assert "Requires: numpy" in run(python, "-m", "pip", "show", "libdem", cwd=outside)
assert tree(source) == before, f"the install wrote into the source tree: {sorted(set(tree(source)) ^ set(before))}"

# The example runs as a user runs it, from the folder outside the repository.
lines = run(python, source / "examples" / "python" / "pour.py", 1000, cwd=outside).splitlines()
assert len(lines) == 22 and lines[0].split()[0] == "step", lines
kinetic = [float(line.split()[2]) for line in lines[1:]]
top = [float(line.split()[4]) for line in lines[2:]]  # mm
assert kinetic[-1] < max(kinetic) and top[-1] < top[0], lines  # the balls fell and the pile settles

# help() explains, and the installed stubs define every public name.
help_text = run(python, "-c", "import pydoc, libdem; print(pydoc.render_doc(libdem.World.step, renderer=pydoc.plaintext))",
                cwd=outside)
assert "Advances the simulation by n time steps" in help_text and "n: steps to take" in help_text, help_text
report = run(python, "-c", f"""
import sys; sys.path.insert(0, {str(source / 'tests' / 'python')!r})
import libdem
from pathlib import Path
from api_names import missing_from_stubs, undocumented
public, missing = missing_from_stubs(libdem, Path(libdem.__file__).with_name("__init__.pyi").read_text())
print(len(public), len(missing), missing, undocumented(libdem))
""", cwd=outside)
count, missing_count, rest = report.split(" ", 2)
assert missing_count == "0" and rest.strip() == "[] []", report
shutil.rmtree(outside)
print(f"pip install -e: {editable:.0f} s, pip install: {regular:.0f} s; the installed stubs define all {count} public names")
