#!/usr/bin/env bash
# `pip install` as docs/python.md shows it, into a fresh virtual environment that sees the
# system's packages (Debian's numpy), offline: then the venv's Python must import sphray from the
# venv itself and answer a query. The ctest python.pip_install runs it.
#   python/pip_install_check.sh PYTHON SOURCE_DIR
set -euo pipefail
python=$1
source_dir=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$python" -m venv --system-site-packages "$work/venv"
"$work/venv/bin/pip" install --no-build-isolation --no-index "$source_dir"
cd "$work"  # not the checkout: nothing there may stand in for the installed module
"$work/venv/bin/python" - "$work/venv" <<'PY'
import sys
from pathlib import Path

import numpy as np
import sphray

venv = Path(sys.argv[1]).resolve()
where = Path(sphray.__file__).resolve()
assert venv in where.parents, f"sphray imported from {where}, not from the venv {venv}"
assert (where.parent / "sphray.pyi").exists(), "the type stubs were not installed"
scene = sphray.Scene(np.float32([[0, 0, -3]]), np.float32([1]))
t, ids = scene.intersect(np.float32([[0, 0, 0]]), np.float32([[0, 0, -1]]))
assert ids[0] == 0 and t[0] == 2.0, (t, ids)
print(f"pip install: sphray {sphray.__version__} from {where}")
PY
