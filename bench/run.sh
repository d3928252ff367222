#!/usr/bin/env bash
# Runs every benchmark once and regenerates docs/performance.md and docs/images/perf-*.png.
#
#   bench/run.sh                      # configure and build the release preset, then run
#   bench/run.sh path/to/sphray_bench [more Google Benchmark flags]
#   bench/run.sh --python-only        # the Python comparisons alone: rewrites only their
#                                     # sections of docs/performance.md and their plots
#
# A full run takes several minutes on a 2-core machine; run it on a quiet one.
#
# The Python module against numpy (bench/python_vs_numpy.py), against Open3D
# (bench/python_vs_open3d.py) and against SciPy's cKDTree (bench/python_vs_ckdtree.py) run too,
# with the module from build/release/python (SPHRAY_PYTHON_DIR overrides);
# bench/install-python-peers installs Open3D and SciPy first unless SPHRAY_BENCH_NO_INSTALL=1.
# Without a library or the module, its section is left out.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

python_only=0
if [[ ${1:-} == --python-only ]]; then
  python_only=1
  shift
  cmake --preset release
  cmake --build --preset release --target sphray_python sphray_kernel_shared
elif [[ $# -ge 1 && -x $1 ]]; then
  bench=$1
  shift
else
  cmake --preset release
  cmake --build --preset release --target sphray_bench
  cmake --build --preset release --target sphray_python sphray_kernel_shared ||
    true   # absent without pybind11
  bench=build/release/bench/sphray_bench
fi

# Debian's matplotlib lives in the system Python; a python3 earlier on PATH may lack it.
python=python3
if ! "$python" -c 'import matplotlib' 2>/dev/null && [[ -x /usr/bin/python3 ]]; then
  python=/usr/bin/python3
fi

out_dir=${SPHRAY_BENCH_OUT:-build/bench-results}
mkdir -p "$out_dir"
json=$out_dir/sphray_bench.json
flags=(--benchmark_min_time=0.2 --benchmark_repetitions=3 --benchmark_report_aggregates_only=true)
if [[ $python_only == 0 ]]; then
  echo "bench/run.sh: $bench ${flags[*]} $*"
  "$bench" "${flags[@]}" "$@" --benchmark_out="$json" --benchmark_out_format=json
fi

# The Python module against numpy and sphray's C calls, then against Open3D, with the system
# Python (Debian's numpy and Open3D).
module_dir=${SPHRAY_PYTHON_DIR:-build/release/python}
numpy_json=$out_dir/python_vs_numpy.json
py_command="bench/run.sh"
[[ $python_only == 0 ]] || py_command="bench/run.sh --python-only"
rm -f "$numpy_json"
if PYTHONPATH=$module_dir /usr/bin/python3 -c 'import sphray' 2>/dev/null; then
  PYTHONPATH=$module_dir /usr/bin/python3 bench/python_vs_numpy.py --out "$numpy_json" \
    --library build/release/kernel/libsphray.so.2 --command "$py_command"
else
  echo "bench/run.sh: the sphray module ($module_dir) is not importable; no numpy section"
fi
open3d_json=$out_dir/python_vs_open3d.json
rm -f "$open3d_json"
[[ ${SPHRAY_BENCH_NO_INSTALL:-0} == 1 ]] || bash bench/install-python-peers || true
if PYTHONPATH=$module_dir /usr/bin/python3 -c 'import open3d, sphray' 2>/dev/null; then
  PYTHONPATH=$module_dir /usr/bin/python3 bench/python_vs_open3d.py --out "$open3d_json"
else
  echo "bench/run.sh: Open3D or the sphray module ($module_dir) not importable; no Open3D section"
fi
ckdtree_json=$out_dir/python_vs_ckdtree.json
rm -f "$ckdtree_json"
if PYTHONPATH=$module_dir /usr/bin/python3 -c 'import scipy, sphray' 2>/dev/null; then
  PYTHONPATH=$module_dir /usr/bin/python3 bench/python_vs_ckdtree.py --out "$ckdtree_json" \
    --command "$py_command"
else
  echo "bench/run.sh: SciPy or the sphray module ($module_dir) not importable; no cKDTree section"
fi

if [[ $python_only == 1 ]]; then
  [[ -f $numpy_json || -f $open3d_json || -f $ckdtree_json ]] ||
    { echo "bench/run.sh: no Python results to report" >&2; exit 1; }
  "$python" bench/report.py --numpy "$numpy_json" --open3d "$open3d_json" \
    --ckdtree "$ckdtree_json"
else
  "$python" bench/report.py "$json" --numpy "$numpy_json" --open3d "$open3d_json" \
    --ckdtree "$ckdtree_json" --command "bench/run.sh (${flags[*]}${*:+ $*})"
fi
