#!/usr/bin/env bash
# Runs every benchmark once and regenerates docs/performance.md and docs/images/perf-*.png.
#
#   bench/run.sh                      # configure and build the release preset, then run
#   bench/run.sh path/to/sphray_bench [more Google Benchmark flags]
#
# A full run takes several minutes on a 2-core machine; run it on a quiet one.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root"

if [[ $# -ge 1 && -x $1 ]]; then
  bench=$1
  shift
else
  cmake --preset release
  cmake --build --preset release --target sphray_bench
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
echo "bench/run.sh: $bench ${flags[*]} $*"
"$bench" "${flags[@]}" "$@" --benchmark_out="$json" --benchmark_out_format=json
"$python" bench/report.py "$json" --command "bench/run.sh (${flags[*]}${*:+ $*})"
