"""pytest setup for the Python API tests: the module is imported from the build tree
(PYTHONPATH=BUILD/python, set by CTest), and the apps are found in LIBDEM_BUILD_DIR/apps."""

import os
from pathlib import Path

import pytest


@pytest.fixture
def apps():
    return Path(os.environ.get("LIBDEM_BUILD_DIR", "build")) / "apps"


# The reduced specimen of the C++ integration tests: 30 mm x 12 mm, 4D balls (about 170), one thread.
REDUCED = {"specimen": {"diameter": 0.03, "height": 0.012}, "engine": {"threads": 1}}
