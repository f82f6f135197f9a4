#!/usr/bin/env bash
# Cross-builds the core modules of deploysim (math, dynamics, model, schedule,
# integrators, analysis) and their tests for aarch64 Linux with Debian's cross compiler,
# and runs the tests under qemu-user. Shows that the accuracy near the separatrix does not
# depend on x87 extended precision (math/double_double.h is all the extra precision).
# Installs what is missing (needs root or sudo): the arm64 architecture, the cross
# compiler, qemu-user and the arm64 GoogleTest and Boost headers (Eigen is arch-free).
# Usage: tools/cross_aarch64.sh [build-dir]   (default build/aarch64)
# Prints the test count and the result; exits non-zero if a test fails.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${1:-build/aarch64}"
start=$(date +%s)

if [ "$(id -u)" -eq 0 ]; then sudo=(); else sudo=(sudo); fi
apt_get() {
  DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get -o DPkg::Lock::Timeout=600 -y -qq "$@"
}
packages=(g++-aarch64-linux-gnu qemu-user libgtest-dev:arm64 libboost1.74-dev:arm64
          libeigen3-dev)
missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "cross_aarch64: installing ${missing[*]}"
  if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    "${sudo[@]}" dpkg --add-architecture arm64
  fi
  apt_get update
  apt_get install --no-install-recommends "${missing[@]}" >/dev/null
fi

cmake -S . -B "$build_dir" -G Ninja \
  -DCMAKE_TOOLCHAIN_FILE="$PWD/cmake/aarch64-linux-gnu.cmake" \
  -DCMAKE_BUILD_TYPE=Release -DDEPLOYSIM_WARNINGS_AS_ERRORS=ON \
  -DDEPLOYSIM_SKIP_MODULES="io;sweep;crosscheck;cli" -DDEPLOYSIM_BUILD_BENCH=OFF \
  >/dev/null
cmake --build "$build_dir" -j"$(nproc)"
built=$(date +%s)

set +e
# The long runs of tests/long_runs.txt stay out, as in the sanitizer step: the short tests
# named beside each run their code paths here, and under qemu they would take minutes.
long_tests=$(tools/long_runs.sh)
ctest --test-dir "$build_dir" -j"$(nproc)" -E "$long_tests" --output-on-failure \
  >"$build_dir/ctest.log" 2>&1
rc=$?
set -e
end=$(date +%s)
tail -n 25 "$build_dir/ctest.log" | grep -vE '^\s*$' | grep -E 'tests passed|Failed|\(Failed\)|Timeout|Total Test' || true
total=$(grep -c 'Test *#' "$build_dir/ctest.log" || true)
echo "cross_aarch64: $(uname -m) host, aarch64 target under $(qemu-aarch64 --version | head -n1)"
echo "cross_aarch64: ${total} tests run under qemu-aarch64, ctest exit code ${rc}"
echo "cross_aarch64: build $((built - start)) s, tests $((end - built)) s, total $((end - start)) s"
exit "$rc"
