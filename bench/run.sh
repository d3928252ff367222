#!/usr/bin/env bash
# Runs every benchmark once and regenerates docs/performance.md and docs/images/perf-*.png.
#
#   bench/run.sh                      # configure and build the release preset, then run
#   bench/run.sh path/to/sphray_bench [more Google Benchmark flags]
#   bench/run.sh --open3d-only        # the Python module against Open3D alone: rewrites only
#                                     # that section of docs/performance.md and its plot
#
# A full run takes several minutes on a 2-core machine; run it on a quiet one.
#
# The Python module against Open3D (bench/python_vs_open3d.py) runs too, with the module from
# build/release/python (SPHRAY_PYTHON_DIR overrides); bench/install-open3d installs Open3D
# first unless SPHRAY_BENCH_NO_INSTALL=1. Without Open3D or the module, that section is left out.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

open3d_only=0
if [[ ${1:-} == --open3d-only ]]; then
  open3d_only=1
  shift
  cmake --preset release
  cmake --build --preset release --target sphray_python
elif [[ $# -ge 1 && -x $1 ]]; then
  bench=$1
  shift
else
  cmake --preset release
  cmake --build --preset release --target sphray_bench
  cmake --build --preset release --target sphray_python || true   # absent without pybind11
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
if [[ $open3d_only == 0 ]]; then
  echo "bench/run.sh: $bench ${flags[*]} $*"
  "$bench" "${flags[@]}" "$@" --benchmark_out="$json" --benchmark_out_format=json
fi

# The Python module against Open3D, with the system Python (Debian's numpy and Open3D).
open3d_json=$out_dir/python_vs_open3d.json
rm -f "$open3d_json"
module_dir=${SPHRAY_PYTHON_DIR:-build/release/python}
[[ ${SPHRAY_BENCH_NO_INSTALL:-0} == 1 ]] || bash bench/install-open3d || true
if PYTHONPATH=$module_dir /usr/bin/python3 -c 'import open3d, sphray' 2>/dev/null; then
  PYTHONPATH=$module_dir /usr/bin/python3 bench/python_vs_open3d.py --out "$open3d_json"
else
  echo "bench/run.sh: Open3D or the sphray module ($module_dir) not importable; no Open3D section"
fi

if [[ $open3d_only == 1 ]]; then
  [[ -f $open3d_json ]] || { echo "bench/run.sh: no Open3D results to report" >&2; exit 1; }
  "$python" bench/report.py --open3d "$open3d_json"
else
  "$python" bench/report.py "$json" --open3d "$open3d_json" --command "bench/run.sh (${flags[*]}${*:+ $*})"
fi
