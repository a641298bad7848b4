#!/usr/bin/env bash
# Benchmark: the settling pile of in.pile (20,000 spheres by default) on 1 and 2 MPI ranks,
# `pair_style dashpot hsd` (through the dashpot C ABI) against LAMMPS's nearest built-in,
# `pair_style granular` with `hertz/material ... damping tsuji tangential linear_nohistory 0 0`.
# Both runs have the same floor (fix wall/gran), integrator and neighbor settings; the score is
# particle-steps per second of the whole run loop (atoms x steps / LAMMPS's "Loop time"), best of
# REPEATS runs, with the two styles alternating so that machine noise hits both.
#
#   DASHPOT_LAMMPS_VENV=/path/to/venv examples/lammps/bench.sh [NSTEPS] [REPEATS]
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="${DASHPOT_LAMMPS_VENV:?set DASHPOT_LAMMPS_VENV}"
nsteps="${1:-1000}"
repeats="${2:-3}"
nx="${BENCH_NX:-20}"
nz="${BENCH_NZ:-50}"
d2="${BENCH_D2:-0.01}"   # 0.008: a bidisperse pile (half the spheres 8 mm)
plugin="$("$here/build.sh" "$root/target/lammps" | tail -n1)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

# prints "particle_steps_per_s pair_seconds loop_seconds"
run() {
    local ranks="$1" style="$2" log="$work/$2.$1.log"
    "$venv/bin/mpirun" -np "$ranks" "$venv/bin/lmp" -log none -in "$here/in.pile" \
        -var style "$style" -var wall fix -var nx "$nx" -var nz "$nz" -var nsteps "$nsteps" -var d2 "$d2" \
        -var plugin "$plugin" -var plugin_dir "$root/target/release" >"$log" 2>&1 ||
        { cat "$log" >&2; exit 1; }
    awk '/^Loop time of/ { t = $4; n = $9; a = $12 } /^Pair  *\|/ { p = $5 }
         END { printf "%.6g %.6g %.6g\n", a * n / t, p, t }' "$log"
}

echo "settling pile: $((nx * nx * nz)) spheres (d2 = $d2 m), $nsteps steps, best of $repeats; $(nproc) cores"
printf "%-6s %-10s %16s %10s %10s\n" ranks style particle-steps/s pair_s loop_s
for ranks in 1 2; do
    best_g=0 best_d=0
    for _ in $(seq "$repeats"); do
        for style in granular dashpot; do
            read -r ps pair loop < <(run "$ranks" "$style")
            printf "%-6s %-10s %16.4g %10.4g %10.4g\n" "$ranks" "$style" "$ps" "$pair" "$loop"
            if [ "$style" = granular ]; then
                best_g=$(awk -v a="$best_g" -v b="$ps" 'BEGIN { print (b > a ? b : a) }')
            else
                best_d=$(awk -v a="$best_d" -v b="$ps" 'BEGIN { print (b > a ? b : a) }')
            fi
        done
    done
    awk -v r="$ranks" -v g="$best_g" -v d="$best_d" 'BEGIN {
        printf "RATIO ranks=%d dashpot=%.4g granular=%.4g particle-steps/s: dashpot/granular = %.2fx\n", r, d, g, d / g }'
done
