"""pytest set-up: the tests import the package from the build tree (build/python/gfmd, or
$GFMD_BUILD_DIR/python/gfmd), which holds what `pip install .` installs."""
import glob
import os
import sys

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.environ.get("GFMD_BUILD_DIR", os.path.join(ROOT, "build"))
PYDIR = os.path.join(BUILD, "python")
if not glob.glob(os.path.join(PYDIR, "gfmd", "_core*.so")):
    pytest.exit(f"the Python package was not built in {PYDIR} (pybind11-dev and python3-dev are needed)", returncode=2)
sys.path.insert(0, PYDIR)
