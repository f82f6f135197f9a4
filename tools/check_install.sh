#!/usr/bin/env bash
# Checks deploysim as a library others build on: installs a build into a scratch prefix
# (cmake --install), then configures, builds and runs, from a copy OUTSIDE the source
# tree and with CMAKE_PREFIX_PATH=<prefix> only,
#   - examples/free_body (find_package(deploysim), deploysim::analysis: an InertiaSource
#     written in code, integrated with rkf78 and checked against the closed form), and
#   - a link check that uses deploysim::io_yaml, ::io and ::sweep (whose static libraries
#     need yaml-cpp, HDF5 and MPI at link time only),
# and checks that no installed header includes yaml-cpp or HDF5.
# Usage: tools/check_install.sh [BUILD_DIR]   (default build/release; configured and built
#        with the release preset when missing)
set -euo pipefail
cd "$(dirname "$0")/.."
src="$PWD"
build="${1:-build/release}"
if [ ! -f "$build/CMakeCache.txt" ]; then
  cmake --preset release >/dev/null
  build=build/release
fi
cmake --build "$build" -j2 >/dev/null

tmp="$(mktemp -d "${TMPDIR:-/tmp}/deploysim_install.XXXXXX")"
trap 'rm -rf "$tmp"' EXIT
prefix="$tmp/prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
echo "check_install: installed into $prefix: $(find "$prefix" -type f | wc -l) files"
for f in bin/deploysim include/deploysim/analysis/free_body_solution.h include/deploysim/version.h \
         lib/cmake/deploysim/deploysimConfig.cmake lib/cmake/deploysim/deploysimConfigVersion.cmake; do
  [ -e "$prefix/$f" ] || { echo "check_install: $f was not installed" >&2; exit 1; }
done
"$prefix/bin/deploysim" --version
# Internals stay private, and every installed header's project includes are installed.
for f in integrators/carry_store.h integrators/lie_anchor.h integrators/driver.h \
         integrators/driver_support.h \
         integrators/rk_engine.h io/number_format.h; do
  [ ! -e "$prefix/include/deploysim/$f" ] || { echo "check_install: internal $f was installed" >&2; exit 1; }
done
missing=$(cd "$prefix/include" && grep -rhoE '#include "deploysim/[^"]+"' deploysim | sort -u |
          sed -E 's/#include "(.*)"/\1/' | while read -r h; do [ -e "$h" ] || echo "$h"; done)
[ -z "$missing" ] || { echo "check_install: installed headers include uninstalled ones: $missing" >&2; exit 1; }
tests/io/header_leaks_test.sh "$src" "yaml_fields.cc,yaml_model.cc,yaml_profile.cc" "$prefix/include"

# The consumers, copied out of the source tree (they must not reach into it).
cp -r examples/free_body "$tmp/free_body"
mkdir -p "$tmp/link_check"
cat >"$tmp/link_check/CMakeLists.txt" <<'CMAKE'
cmake_minimum_required(VERSION 3.22)
project(deploysim_link_check LANGUAGES CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(deploysim REQUIRED)
add_executable(read_model read_model.cpp)
target_link_libraries(read_model PRIVATE deploysim::io_yaml)
add_executable(load_sweep load_sweep.cpp)
target_link_libraries(load_sweep PRIVATE deploysim::sweep deploysim::io)
CMAKE
cat >"$tmp/link_check/read_model.cpp" <<'CPP'
#include <deploysim/io/yaml_reader.h>
#include <cstdio>
int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const deploysim::model::Model m = deploysim::io::LoadModel(argv[1]);
  std::printf("read_model: %s, %zu configurations\n", m.name.c_str(), m.configurations.size());
  return m.configurations.empty() ? 1 : 0;
}
CPP
cat >"$tmp/link_check/load_sweep.cpp" <<'CPP'
#include <deploysim/sweep/sweep_file.h>
#include <deploysim/version.h>
#include <cstdio>
int main(int argc, char** argv) {
  if (argc != 2) return 2;
  const deploysim::sweep::SweepSpec s = deploysim::sweep::LoadSweep(argv[1]);
  std::printf("load_sweep: %s, %zu cases (%s)\n", s.name.c_str(), s.case_count(),
              deploysim::kBuildId);
  return s.case_count() > 0 ? 0 : 1;
}
CPP

for project in free_body link_check; do
  cmake -S "$tmp/$project" -B "$tmp/$project/build" -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_BUILD_TYPE=Release >"$tmp/$project.log" 2>&1 ||
    { cat "$tmp/$project.log" >&2; echo "check_install: $project: configure failed" >&2; exit 1; }
  cmake --build "$tmp/$project/build" -j2 >>"$tmp/$project.log" 2>&1 ||
    { cat "$tmp/$project.log" >&2; echo "check_install: $project: build failed" >&2; exit 1; }
done
"$tmp/free_body/build/free_body"
# Data files are inputs, not part of the package: read the repository's.
"$tmp/link_check/build/read_model" "$src/models/smallsat.yaml"
"$tmp/link_check/build/load_sweep" "$src/sweeps/smallsat_duration_spin.yaml"
# The installed CLI's Python subcommands run the installed tools (share/deploysim/tools),
# which the installed binary looks for before the source tree's.
for f in report.py view.py view_template.html deploysim_scene.py deploysim_results.py \
         plot_trajectory.py plot_geometry.py; do
  [ -f "$prefix/share/deploysim/tools/$f" ] || { echo "check_install: tools/$f was not installed" >&2; exit 1; }
done
"$prefix/bin/deploysim" simulate "$src/deployment_profiles/wing_nut.yaml" -q -o "$tmp/wing_nut.h5"
env -u DEPLOYSIM_TOOLS_DIR "$prefix/bin/deploysim" view "$tmp/wing_nut.h5" -o "$tmp/wing_nut.html"
[ -s "$tmp/wing_nut.html" ] || { echo "check_install: deploysim view wrote nothing" >&2; exit 1; }
# The Python package, where built: imported from the prefix alone (not the build tree).
if [ -d "$prefix/lib/python3/dist-packages/deploysim" ]; then
  (cd "$tmp" && env -u PYTHONPATH PYTHONPATH="$prefix/lib/python3/dist-packages" /usr/bin/python3 -c "
import deploysim, sys
assert deploysim.__file__.startswith('$prefix'), deploysim.__file__
r = deploysim.simulate('$src/deployment_profiles/wing_nut.yaml', dt=1.0)
print('check_install: python package', deploysim.__version__, len(r.time), 'samples,', len(r.flips), 'flips')
")
fi
echo "check_install: OK"
