#!/usr/bin/env bash
# Fails when a library header leaks a dependency (STYLE.md "only io includes
# yaml-cpp and HDF5"):
#   1. yaml-cpp and HDF5 are included only by io's .cc files and io's private
#      hdf5_common.h, which in turn only io's .cc files include;
#   2. the io_yaml library (reading models, profiles, sweep files) includes nothing of
#      the integrators, analysis, sweep or of the rest of io: reading a model must not pull
#      in the integrators;
#   3. (optional) no header in an installed include folder includes yaml-cpp or HDF5.
# Usage: header_leaks_test.sh SOURCE_DIR IO_YAML_SOURCES [INSTALLED_INCLUDE_DIR]
#        (IO_YAML_SOURCES: the io_yaml library's .cc files, comma-separated, in
#        src/deploysim/io; its headers are theirs, x.cc's x.h, and the readers' umbrella
#        yaml_reader.h)
set -euo pipefail
src="$1/src/deploysim"
IFS=',;' read -r -a yaml_files <<<"$2"
installed="${3:-}"
fail=0
report() { echo "LEAK: $*" >&2; fail=1; }

dep='#[[:space:]]*include[[:space:]]*[<"](yaml-cpp/|H5[A-Za-z]*\.h|hdf5)'
while IFS= read -r hit; do
  file="${hit%%:*}"
  case "$file" in
    "$src"/io/*.cc | "$src"/io/hdf5_common.h) ;;
    *) report "$hit (only io's .cc files may include yaml-cpp or HDF5)" ;;
  esac
done < <(grep -rnE "$dep" "$src" || true)

while IFS= read -r hit; do
  file="${hit%%:*}"
  case "$file" in
    "$src"/io/*.cc) ;;
    *) report "$hit (io/hdf5_common.h is private to io's .cc files)" ;;
  esac
done < <(grep -rn 'deploysim/io/hdf5_common.h' "$src" || true)

[ "${#yaml_files[@]}" -gt 0 ] || { echo "no io_yaml files given" >&2; exit 2; }
for f in "${yaml_files[@]}"; do yaml_files+=("${f%.cc}.h"); done
yaml_files+=(yaml_reader.h)
for f in "${yaml_files[@]}"; do
  path="$src/io/$(basename "$f")"
  [ -f "$path" ] || { report "$path: io_yaml file not found"; continue; }
  while IFS= read -r hit; do
    report "$path:$hit (io_yaml must not depend on the integrators, analysis or the rest of io)"
  done < <(grep -nE '#[[:space:]]*include[[:space:]]*"deploysim/(integrators|analysis|sweep|crosscheck|cli)/' "$path" || true)
  while IFS= read -r hit; do
    inc=$(sed -E 's|.*"deploysim/io/([^"]*)".*|\1|' <<<"$hit")
    own=0
    for g in "${yaml_files[@]}"; do [ "$(basename "$g")" = "$inc" ] && own=1; done
    [ "$own" -eq 1 ] || report "$path:$hit (io_yaml includes only its own io headers)"
  done < <(grep -nE '#[[:space:]]*include[[:space:]]*"deploysim/io/' "$path" || true)
done

if [ -n "$installed" ]; then
  [ -d "$installed/deploysim" ] || { report "$installed/deploysim: no installed headers"; }
  while IFS= read -r hit; do
    report "$hit (an installed header includes yaml-cpp or HDF5)"
  done < <(grep -rnE "$dep" "$installed/deploysim" || true)
  [ ! -e "$installed/deploysim/io/hdf5_common.h" ] || report "io/hdf5_common.h is installed"
fi

if [ "$fail" -ne 0 ]; then exit 1; fi
echo "no header leaks ($(grep -rlE '#[[:space:]]*include' "$src" | wc -l) files checked)"
