#!/usr/bin/env bash
# Fuzzes deploysim's YAML entry points with libFuzzer under ASan+UBSan (fuzz/README.md):
# fuzz_model (io::LoadModel), fuzz_profile (io::LoadProfile), fuzz_sweep (sweep::ReadSweep, then
# ValidateCases for sweeps of at most 64 cases: LoadSweep with its time bounded).
#
# Usage:
#   tools/fuzz.sh [options] SECONDS [TARGET...]   build, seed, fuzz each target SECONDS s
#   tools/fuzz.sh [options] --replay DIR...       build, run every file under DIR through
#                                                 every target once (regression)
#   tools/fuzz.sh --build                         configure and build only
# TARGET: model, profile, sweep (default: all three).
# Options:
#   -j N          targets fuzzed at a time (default 2)
#   --keep-going  fork mode (-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1):
#                 go on after a finding and collect them all (exploration); without it a
#                 target stops at its first finding.
# Limits per input: -timeout=1 (s), -rss_limit_mb=256, -malloc_limit_mb=256, inputs up to
# -max_len=65536 bytes. A finding (crash, UB, leak, timeout, out-of-memory, an exception
# other than std::invalid_argument / std::runtime_error, or an error message that is not one
# short line) is written to build/fuzz/artifacts/TARGET/; the exit status is 1 if there was
# any. CI: `tools/fuzz.sh --replay fuzz/regressions && tools/fuzz.sh 30`.
#
# Build dir: build/fuzz (override with DEPLOYSIM_FUZZ_BUILD); seed corpus build/fuzz/seeds
# (regenerated from the shipped YAML files at each run); the corpus the fuzzer grows is kept
# in build/fuzz/corpus/TARGET across runs; logs in build/fuzz/logs/.
set -euo pipefail

root=$(cd "$(dirname "$0")/.." && pwd)
build=${DEPLOYSIM_FUZZ_BUILD:-$root/build/fuzz}
all_targets=(model profile sweep)
timeout_s=1
memory_mb=256
max_len=65536

usage() { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }

jobs=2
keep_going=0
mode=fuzz
seconds=
replay_dirs=()
targets=()
while [ $# -gt 0 ]; do
  case "$1" in
    -j) jobs=$2; shift 2 ;;
    -j[0-9]*) jobs=${1#-j}; shift ;;
    --keep-going) keep_going=1; shift ;;
    --build) mode=build; shift ;;
    --replay)
      mode=replay; shift
      while [ $# -gt 0 ] && [ -d "$1" ]; do replay_dirs+=("$1"); shift; done
      [ ${#replay_dirs[@]} -gt 0 ] || { echo "fuzz.sh: --replay needs a folder" >&2; exit 2; }
      ;;
    -h|--help) usage ;;
    model|profile|sweep) targets+=("$1"); shift ;;
    *)
      if [[ "$1" =~ ^[0-9]+$ ]] && [ -z "$seconds" ]; then seconds=$1; shift
      else echo "fuzz.sh: unknown argument '$1'" >&2; usage; fi
      ;;
  esac
done
[ ${#targets[@]} -gt 0 ] || targets=("${all_targets[@]}")
if [ "$mode" = fuzz ] && [ -z "$seconds" ]; then usage; fi

# --- build -----------------------------------------------------------------------------
command -v clang++ >/dev/null || { echo "fuzz.sh: clang++ missing (tools/install_deps.sh)" >&2; exit 1; }
start=$(date +%s)
# Only the libraries the loaders need (no Simbody cross-check, no CLI, no MPI).
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" \
  -DDEPLOYSIM_FUZZ=ON "-DDEPLOYSIM_SANITIZERS=address;undefined" \
  "-DDEPLOYSIM_SANITIZERS_EXCLUDE=alignment;null" \
  -DDEPLOYSIM_WARNINGS_AS_ERRORS=ON -DDEPLOYSIM_BUILD_TESTS=OFF -DDEPLOYSIM_BUILD_BENCH=OFF \
  "-DDEPLOYSIM_SKIP_MODULES=crosscheck;cli" -DDEPLOYSIM_WITH_MPI=OFF >/dev/null
cmake --build "$build" -j2 --target "${targets[@]/#/fuzz_}" >"$build/build.log" 2>&1 ||
  { tail -40 "$build/build.log" >&2; echo "fuzz.sh: build failed ($build/build.log)" >&2; exit 1; }
echo "fuzz.sh: built ${targets[*]/#/fuzz_} in $(( $(date +%s) - start )) s ($build)"
[ "$mode" = build ] && exit 0

# --- common run settings -----------------------------------------------------------------
# ASan's quarantine (256 MB by default) would count against the 256 MB RSS limit: keep it
# small. Leaks are findings (libFuzzer's leak check at the end of each input).
export ASAN_OPTIONS=${ASAN_OPTIONS:-quarantine_size_mb=16:detect_leaks=1:allocator_may_return_null=0}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}
export DEPLOYSIM_SOURCE_DIR=$root
# The work folders of the targets (fuzz/fuzz_support.h) in a private tmpfs folder.
shm=/dev/shm
[ -d "$shm" ] && [ -w "$shm" ] || shm=${TMPDIR:-/tmp}
work=$(mktemp -d "$shm/deploysim_fuzz_run.XXXXXX")
trap 'rm -rf "$work"' EXIT
export TMPDIR=$work
limits=(-timeout=$timeout_s -rss_limit_mb=$memory_mb -malloc_limit_mb=$memory_mb
        -max_len=$max_len)
mkdir -p "$build/logs" "$build/artifacts"

# --- replay --------------------------------------------------------------------------------
if [ "$mode" = replay ]; then
  mapfile -t files < <(find "${replay_dirs[@]}" -type f ! -name 'README*' ! -name '.*' | sort)
  echo "fuzz.sh: replaying ${#files[@]} files through ${targets[*]}"
  [ ${#files[@]} -gt 0 ] || exit 0
  failed=0
  for t in "${targets[@]}"; do
    log=$build/logs/replay_$t.log
    # libFuzzer prints a heap profile before it reports an out-of-memory input, which takes
    # minutes for millions of small blocks (the yaml-cpp ',' loop): a hard limit of 30 s a file.
    if timeout -k 5 $((30 * ${#files[@]})) "$build/fuzz/fuzz_$t" "${limits[@]}" -runs=1 \
         "${files[@]}" </dev/null >"$log" 2>&1; then
      echo "  $t: ${#files[@]} files ok"
      continue
    fi
    # One run stops at the first failure: find every failing file.
    for f in "${files[@]}"; do
      if ! timeout -k 5 30 "$build/fuzz/fuzz_$t" "${limits[@]}" -runs=1 "$f" </dev/null \
           >"$build/logs/replay_one.log" 2>&1; then
        what=$(grep -m1 -E 'ERROR: libFuzzer|ERROR: AddressSanitizer|runtime error|deploysim fuzz:|ERROR: LeakSanitizer' \
               "$build/logs/replay_one.log" || echo "killed after 30 s or exit status non-zero")
        echo "  $t: FAIL $f: $what"
        failed=1
      fi
    done
  done
  exit $failed
fi

# --- seeds ---------------------------------------------------------------------------------
# The shipped files, the test inputs, and the YAML examples of the docs (fenced ```yaml
# blocks); regenerated each run so that they follow the repository.
seeds=$build/seeds
rm -rf "$seeds"; mkdir -p "$seeds"
for d in models deployment_profiles sweeps tests/io/bad_inputs fuzz/regressions; do
  [ -d "$root/$d" ] || continue
  find "$root/$d" -type f -name '*.yaml' | while read -r f; do
    cp "$f" "$seeds/$(echo "${f#"$root"/}" | tr / _)"
  done
done
for doc in "$root"/docs/*.md "$root"/README.md; do
  awk -v out="$seeds/$(basename "$doc" .md)_" '
    /^```yaml/ { n++; inside = 1; next }
    /^```/     { inside = 0; next }
    inside     { print > (out n ".yaml") }' "$doc"
done
echo "fuzz.sh: $(find "$seeds" -type f | wc -l) seed files in $seeds"

# --- fuzz ----------------------------------------------------------------------------------
fuzz_one() {
  local t=$1 corpus=$build/corpus/$1 artifacts=$build/artifacts/$1/ extra=()
  mkdir -p "$corpus" "$artifacts"
  if [ "$keep_going" = 1 ]; then
    extra=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
  fi
  touch "$build/logs/$t.start"
  "$build/fuzz/fuzz_$t" "${limits[@]}" -max_total_time="$seconds" -print_final_stats=1 \
    -dict="$root/fuzz/deploysim.dict" -artifact_prefix="$artifacts" "${extra[@]}" \
    "$corpus" "$seeds" </dev/null >"$build/logs/$t.log" 2>&1
}

echo "fuzz.sh: fuzzing ${targets[*]} for $seconds s each, $jobs at a time" \
     "(timeout ${timeout_s} s, ${memory_mb} MB, inputs up to $max_len bytes)"
declare -A status
running=0
for t in "${targets[@]}"; do
  if [ "$running" -ge "$jobs" ]; then wait -n || true; running=$((running - 1)); fi
  ( rc=0; fuzz_one "$t" || rc=$?; echo "$rc" >"$build/logs/$t.rc" ) &
  running=$((running + 1))
done
wait

# --- report --------------------------------------------------------------------------------
set +o pipefail  # a statistic missing from a log is shown as '?'
total_findings=0
printf '%-8s %12s %8s %7s %7s %7s %8s %9s  %s\n' target executions exec/s cov ft corpus \
       rss_MB findings status
for t in "${targets[@]}"; do
  log=$build/logs/$t.log
  rc=$(cat "$build/logs/$t.rc")
  # The new artefacts of this run (crash-, timeout-, oom-, leak-, slow-unit- files).
  findings=$(find "$build/artifacts/$t" -type f -newer "$build/logs/$t.start" \
             ! -name 'slow-unit-*' | wc -l)
  execs=$(grep -oE 'stat::number_of_executed_units: [0-9]+' "$log" | awk '{s += $2} END {print s + 0}')
  rate=$(grep -oE 'stat::average_exec_per_sec: [0-9]+' "$log" | tail -1 | awk '{print $2}')
  rss=$(grep -oE 'stat::peak_rss_mb: +[0-9]+' "$log" | tail -1 | awk '{print $2}')
  # The last status line: "#N ... cov: C ft: F corp: K/..."
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(echo "$last" | grep -oE 'cov: [0-9]+' | awk '{print $2}')
  ft=$(echo "$last" | grep -oE 'ft: [0-9]+' | awk '{print $2}')
  corp=$(echo "$last" | grep -oE 'corp: [0-9]+' | awk '{print $2}')
  if [ "$keep_going" = 1 ] || [ -z "$rate" ]; then
    # Fork mode prints no final stats of the children: the last status line has them.
    execs=$(echo "$last" | sed -E 's/^#([0-9]+).*/\1/')
    rate=$(echo "$last" | grep -oE 'exec/s:? [0-9]+' | awk '{print $2}')
  fi
  st=ok
  if [ "$findings" -gt 0 ] || [ "$rc" != 0 ]; then
    st="FINDINGS (rc $rc; $log)"
    [ "$findings" -gt 0 ] || findings=1
  fi
  total_findings=$((total_findings + findings))
  printf '%-8s %12s %8s %7s %7s %7s %8s %9s  %s\n' "$t" "${execs:-?}" "${rate:-?}" \
         "${cov:-?}" "${ft:-?}" "${corp:-?}" "${rss:-?}" "$findings" "$st"
  find "$build/artifacts/$t" -type f -newer "$build/logs/$t.start" ! -name 'slow-unit-*' |
    sed 's/^/    /'
done
[ "$total_findings" -eq 0 ] || { echo "fuzz.sh: $total_findings finding(s)"; exit 1; }
echo "fuzz.sh: no findings"
