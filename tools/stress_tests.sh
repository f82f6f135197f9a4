#!/usr/bin/env bash
# Runs the whole test suite N times in a row on a loaded machine, to find tests that fail
# only when the machine is busy (a test that waits by sleeping, or races the program it
# drives). Beside the suite run BUSY processes that each keep a core busy, and one that
# writes to the disk. Builds the preset first (nothing when it is up to date).
# Usage: tools/stress_tests.sh [-n N] [--preset release|asan] [--busy K] [-R REGEX]
#   -n N        runs of the suite (default 20)
#   --preset P  the build and test preset (default release)
#   --busy K    CPU-bound processes beside the suite (default 2)
#   -R REGEX    only the tests whose name matches (ctest -R)
# Prints one line per run and, at the end, every failed test with how many runs it failed
# in; exits 1 if any test failed. Logs: build/<preset>/stress/run<i>.log.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=20
preset=release
busy=2
filter=()
while [ $# -gt 0 ]; do
  case "$1" in
    -n) runs=$2; shift 2 ;;
    --preset) preset=$2; shift 2 ;;
    --busy) busy=$2; shift 2 ;;
    -R) filter=(-R "$2"); shift 2 ;;
    -h|--help) sed -n '2,12p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "stress_tests.sh: unknown argument '$1' (--help)" >&2; exit 2 ;;
  esac
done
[[ "$runs" =~ ^[1-9][0-9]*$ ]] || { echo "stress_tests.sh: -n needs a positive count" >&2; exit 2; }
[[ "$busy" =~ ^[0-9]+$ ]] || { echo "stress_tests.sh: --busy needs a count" >&2; exit 2; }

cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" >/dev/null
logs="build/$preset/stress"
mkdir -p "$logs"

loaders=()
cleanup() {
  [ ${#loaders[@]} -eq 0 ] || kill "${loaders[@]}" 2>/dev/null || true
  wait 2>/dev/null || true
  rm -f "$logs/disk_writer.tmp"
}
trap cleanup EXIT
for _ in $(seq 1 "$busy"); do
  (while :; do :; done) &
  loaders+=($!)
done
# A disk writer: 64 MiB written and flushed over and over.
(while :; do dd if=/dev/zero of="$logs/disk_writer.tmp" bs=1M count=64 conv=fsync status=none; done) &
loaders+=($!)

declare -A failed_count=()
total_failures=0
start=$(date +%s)
for i in $(seq 1 "$runs"); do
  t0=$(date +%s)
  log="$logs/run$i.log"
  rc=0
  ctest --preset "$preset" -j2 "${filter[@]}" >"$log" 2>&1 || rc=$?
  # ctest's summary: "  12 - Suite.Name (Failed)" below "The following tests FAILED:".
  mapfile -t names < <(sed -n '/The following tests FAILED:/,$p' "$log" |
                       sed -nE 's/^[[:space:]]*[0-9]+ - (.+) \(([A-Za-z ]+)\).*$/\1 (\2)/p')
  summary=$(grep -E 'tests passed' "$log" | tail -n1 || true)
  if [ "$rc" -ne 0 ] && [ ${#names[@]} -eq 0 ]; then names=("ctest itself (exit code $rc)"); fi
  for n in "${names[@]}"; do
    failed_count["$n"]=$(( ${failed_count["$n"]:-0} + 1 ))
    total_failures=$((total_failures + 1))
  done
  echo "run $i/$runs: ${summary:-no summary} ($(( $(date +%s) - t0 )) s)${names[*]:+; failed: ${names[*]}}"
done

echo "stress_tests: $runs runs of the suite ($preset) beside $busy busy processes and a disk" \
     "writer in $(( $(date +%s) - start )) s: $total_failures failures"
for n in "${!failed_count[@]}"; do echo "  ${failed_count[$n]}x $n"; done
[ "$total_failures" -eq 0 ]
