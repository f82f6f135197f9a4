#!/usr/bin/env bash
# Peak memory of `deploysim simulate` against the number of output samples (issue 10:
# the output is streamed, so memory must not grow with the horizon). The wing nut
# (deployment_profiles/wing_nut.yaml) over 999.9 s, sampled every 1e-2, 1e-3 and 1e-4 s:
# about 1e5, 1e6 and 1e7 samples (1e7: the documented maximum, kMaxOutputSamples). Each run is one
# child of a fresh python3 process, whose getrusage(RUSAGE_CHILDREN).ru_maxrss is the
# child's peak resident set size.
# Usage: bench/rss_bench.sh DEPLOYSIM [--quick] [--markdown FILE] [--baseline OLD_DEPLOYSIM]
#   --quick: 1e5 and 1e6 samples only; --baseline: the same runs with another binary
#   (e.g. the one before streaming) in a second column.
set -euo pipefail
cd "$(dirname "$0")/.."
cli=${1:?usage: bench/rss_bench.sh DEPLOYSIM [--quick] [--markdown FILE] [--baseline OLD]}
shift
quick=0
markdown=""
baseline=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) quick=1 ;;
    --markdown) markdown=$2; shift ;;
    --baseline) baseline=$2; shift ;;
    *) echo "bench/rss_bench.sh: unknown option $1" >&2; exit 2 ;;
  esac
  shift
done

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
dts=(1e-2 1e-3 1e-4)
[[ $quick == 1 ]] && dts=(1e-2 1e-3)

# peak_rss BINARY DT -> "<max RSS in MiB> <wall seconds> <output MiB>" or "failed"
peak_rss() {
  sed -e "s#^model: .*#model: $PWD/models/wing_nut.yaml#" -e 's/until: 40}/until: 999.9}/' \
      -e "s/^  dt: .*/  dt: $2/" deployment_profiles/wing_nut.yaml >"$work/p.yaml"
  /usr/bin/python3 - "$1" "$work/p.yaml" "$work/out.h5" <<'EOF'
import os, resource, subprocess, sys, time
t = time.monotonic()
r = subprocess.run([sys.argv[1], "simulate", sys.argv[2], "-o", sys.argv[3], "-q"])
wall = time.monotonic() - t
if r.returncode != 0:
    print("failed")
else:
    rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss / 1024.0  # KiB -> MiB
    print(f"{rss:.0f} {wall:.1f} {os.path.getsize(sys.argv[3]) / 2**20:.0f}")
EOF
  rm -f "$work/out.h5"
}

rows=()
for dt in "${dts[@]}"; do
  samples=$(/usr/bin/python3 -c "print(round(999.9 / $dt) + 1)")
  read -r rss wall size <<<"$(peak_rss "$cli" "$dt")"
  row="| $samples | $dt | $size | $rss | $wall |"
  if [[ -n $baseline ]]; then
    read -r brss bwall _ <<<"$(peak_rss "$baseline" "$dt")"
    row="$row ${brss:-failed} | ${bwall:--} |"
  fi
  rows+=("$row")
  echo "$row"
done

{
  echo "**Peak memory of \`deploysim simulate\`** (bench/rss_bench.sh): the wing nut over 999.9 s,"
  echo "rkmk-rkf78 at rtol 1e-12, written to HDF5 as it runs. Peak resident set size"
  echo "(getrusage RUSAGE_CHILDREN ru_maxrss) of one run each. Nothing is kept per sample (the"
  echo "samples go to the file in blocks of 4096, the output times are computed on demand);"
  echo "the slight growth is HDF5's metadata cache (the chunk index), which HDF5 bounds."
  echo
  if [[ -n $baseline ]]; then
    echo "| samples | output dt [s] | file [MiB] | peak RSS [MiB] | wall [s] | before streaming: peak RSS [MiB] | wall [s] |"
    echo "|---:|---:|---:|---:|---:|---:|---:|"
  else
    echo "| samples | output dt [s] | file [MiB] | peak RSS [MiB] | wall [s] |"
    echo "|---:|---:|---:|---:|---:|"
  fi
  printf '%s\n' "${rows[@]}"
  echo
  echo "Machine: $(uname -m), $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //')."
} >"$work/table.md"
if [[ -n $markdown ]]; then cp "$work/table.md" "$markdown"; fi
