#!/usr/bin/env bash
# Benchmark: LAMMPS's own granular decks switched by one word (BENCH_DECK=flatwall, drum, chute,
# pour2d: the setups of examples/granular/in.pour.flatwall, in.pour.drum, examples/pour/in.pour
# and in.pour.2d, at LAMMPS's sizes unless BENCH_N/BENCH_NSTEPS say otherwise), each run with
# pair_style granular (or gran/*) and with pair_style dashpot on the same deck, the walls
# LAMMPS's own unless BENCH_WALLS=dashpot; or BENCH_DECK=restitution, the two spheres of
# examples/granular/in.restitution colliding head on over its 1 ms in BENCH_NSTEPS steps
# (100,000 by default, dt = 10 ns; LAMMPS's deck takes 1,000,000 of 1 ns): with two atoms, the
# pair styles' cost per step and call rather than per contact; or the settling pile of in.pile
# (20,000 spheres by default) on 1 and 2 MPI ranks,
# with Mindlin friction and history (BENCH_FRICTION=mindlin, the default) or without (none);
# or the polydisperse frictional pour of in.pour (BENCH_DECK=pour, 2,000 spheres, fix pour, in a
# box BENCH_L = 0.08 m wide, whose pile stays below the region fix pour inserts into: both
# styles pour the same spheres),
# with rolling resistance too when BENCH_ROLLING=sds (`rolling sds` with k = BENCH_KR N/m,
# gamma = BENCH_GR N s/m, mu = BENCH_MUR in both styles, on the pairs and the floor).
# `pair_style dashpot hsd` (through the dashpot C ABI) against LAMMPS's nearest built-in,
# `pair_style granular` with `hertz/material ... damping coeff_restitution` (for Hertz the same
# alpha(eps) as hsd) and the same friction (`tangential mindlin NULL 0 MU` against dashpot's
# `tangential mindlin mu=MU`, or `linear_nohistory 0 0` without friction).
# Both runs have the same floor (fix wall/gran), integrator and neighbor settings. Each repeat
# runs the two styles one after the other (granular first in odd pairs, dashpot first in even
# ones, so that machine noise hits both and neither always runs second); the
# score is the CPU seconds of LAMMPS's run loops ("Loop time" x processes x "% CPU use"), and
# the ratio is the median over the repeats of each pair's granular/dashpot ratio. Particle-steps
# per second (atoms x steps / loop time) are printed beside. Each run's RESULT line goes to
# stderr.
#
#   DASHPOT_LAMMPS_VENV=/path/to/venv examples/lammps/bench.sh [NSTEPS] [REPEATS]
# (BENCH_RANKS="1 2" by default: the MPI rank counts to run)
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
venv="${DASHPOT_LAMMPS_VENV:?set DASHPOT_LAMMPS_VENV}"
nsteps="${1:-1000}"
repeats="${2:-3}"
nx="${BENCH_NX:-20}"
nz="${BENCH_NZ:-50}"
d2="${BENCH_D2:-0.01}"   # 0.008: a bidisperse pile (half the spheres 8 mm)
friction="${BENCH_FRICTION:-mindlin}"
deck="${BENCH_DECK:-pile}"
rolling="${BENCH_ROLLING:-none}"
plugin="$("$here/build.sh" "$root/target/lammps" | tail -n1)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cd "$work"

# prints "cpu_seconds particle_steps_per_s pair_seconds loop_seconds"
run() {
    local ranks="$1" style="$2" log="$work/$2.$1.log"
    local file="in.$deck"
    # LAMMPS's own walls under granular; BENCH_WALLS chooses dashpot's (the wall fixes compared)
    local walls="${BENCH_WALLS:-gran}"
    [ "$style" = granular ] && walls=gran
    case "$deck" in
        flatwall | drum | chute) file="in.pour.$deck" ;;
        pour2d) file="in.pour.2d" ;;
        restitution) file="in.restitution" ;;
    esac
    if [ "$deck" = flatwall ]; then
        set -- -var walls "$walls" -var n "${BENCH_N:-1500}" -var nsteps "${BENCH_NSTEPS:-5000}"
    elif [ "$deck" = drum ]; then
        set -- -var walls "$walls" -var n "${BENCH_N:-2000}" -var fill "${BENCH_FILL:-2000}" \
            -var spin "${BENCH_NSTEPS:-3000}"
    elif [ "$deck" = chute ]; then
        set -- -var walls "$walls" -var n "${BENCH_N:-3000}" -var pour "${BENCH_NSTEPS:-25000}" \
            -var flow "${BENCH_NSTEPS:-25000}"
    elif [ "$deck" = pour2d ]; then
        set -- -var walls "$walls" -var n "${BENCH_N:-1000}" -var nsteps "${BENCH_NSTEPS:-25000}"
    elif [ "$deck" = restitution ]; then
        set -- -var dt "$(awk -v n="${BENCH_NSTEPS:-100000}" 'BEGIN { printf "%.10g", 1e-3 / n }')"
    elif [ "$deck" = pour ]; then
        set -- -var n "${BENCH_N:-2000}" -var L "${BENCH_L:-0.08}" -var tpour "${BENCH_TPOUR:-0.8}" \
            -var tsettle "${BENCH_TSETTLE:-0.2}" \
            -var rolling "$rolling" -var kr "${BENCH_KR:-1e4}" -var gr "${BENCH_GR:-0.1}" -var mur "${BENCH_MUR:-1.0}"
    else
        set -- -var nx "$nx" -var nz "$nz" -var nsteps "$nsteps" -var d2 "$d2" -var friction "$friction" \
            -var wall fix
    fi
    "$venv/bin/mpirun" -np "$ranks" "$venv/bin/lmp" -log none -in "$here/$file" \
        -var style "$style" "$@" \
        -var plugin "$plugin" -var plugin_dir "$root/target/release" >"$log" 2>&1 ||
        { cat "$log" >&2; exit 1; }
    # the deck's own result line (the settled pile's measures for the pour), to stderr; a run
    # without one, or whose pile lost atoms, sank through the floor or went non-finite, is no
    # benchmark: stop rather than print a ratio
    local result
    result="$(grep '^RESULT' "$log")" || { echo "$style on $ranks rank(s): no RESULT line" >&2; cat "$log" >&2; exit 1; }
    echo "ranks=$ranks $result" >&2
    if [ "$deck" = pile ]; then
        echo "$result" | awk -v want="$((nx * nx * nz))" -v d="0.01" '{
            for (i = 2; i <= NF; i++) { split($i, kv, "="); v[kv[1]] = kv[2] }
            ok = v["atoms"] == want && v["vrms"] !~ /nan|inf/ &&
                 v["zmin"] > -0.5 * d && v["zmax"] !~ /nan|inf/
            if (!ok) { print "not a sane pile (want " want " atoms, none below the floor, finite): " $0; exit 1 }
        }' >&2 || exit 1
    fi
    # every run of the deck: CPU seconds of the loops, particle-steps over loop time, summed
    awk '/^Loop time of/ { t += $4; ps += $9 * $12; lt = $4; np = $6 }
         /% CPU use with/ { cpu += lt * np * $1 / 100 } /^Pair  *\|/ { p += $5 }
         END { if (t <= 0) exit 1; printf "%.6g %.6g %.6g %.6g\n", cpu, ps / t, p, t }' "$log" ||
        { echo "$style on $ranks rank(s): no loop time" >&2; exit 1; }
}

case "$deck" in
    flatwall | drum | chute | pour2d)
        echo "LAMMPS's $deck deck: granular against dashpot (walls ${BENCH_WALLS:-gran}), $repeats pairs; $(nproc) cores" ;;
esac
if [ "$deck" = restitution ]; then
    echo "in.restitution: 2 spheres, ${BENCH_NSTEPS:-100000} steps, granular against dashpot, $repeats pairs; $(nproc) cores"
elif [ "$deck" = pour ]; then
    echo "polydisperse pour: ${BENCH_N:-2000} spheres, rolling $rolling, $repeats pairs; $(nproc) cores"
elif [ "$deck" = pile ]; then
    echo "settling pile: $((nx * nx * nz)) spheres (d2 = $d2 m, friction $friction), $nsteps steps, $repeats pairs; $(nproc) cores"
fi
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2 ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2) }'; }
printf "%-6s %-10s %10s %16s %10s %10s\n" ranks style cpu_s particle-steps/s pair_s loop_s
for ranks in ${BENCH_RANKS:-1 2}; do
    ratios="" pratios="" cpu_g="" cpu_d=""
    for rep in $(seq "$repeats"); do
        # the order alternates from pair to pair, so that neither style always runs second
        order="granular dashpot"
        [ $((rep % 2)) -eq 0 ] && order="dashpot granular"
        for style in $order; do
            read -r cpu ps pair loop < <(run "$ranks" "$style")
            printf "%-6s %-10s %10.4g %16.4g %10.4g %10.4g\n" "$ranks" "$style" "$cpu" "$ps" "$pair" "$loop"
            if [ "$style" = granular ]; then
                g=$cpu gp=$pair cpu_g="$cpu_g $cpu"
            else
                d=$cpu dp=$pair cpu_d="$cpu_d $cpu"
            fi
        done
        ratios="$ratios $(awk -v g="$g" -v d="$d" 'BEGIN { print g / d }')"
        pratios="$pratios $(awk -v g="$gp" -v d="$dp" 'BEGIN { print (d > 0 ? g / d : 0) }')"
    done
    mg=$(echo $cpu_g | tr ' ' '\n' | median) md=$(echo $cpu_d | tr ' ' '\n' | median)
    mr=$(echo $ratios | tr ' ' '\n' | median) mp=$(echo $pratios | tr ' ' '\n' | median)
    printf "RATIO ranks=%s CPU seconds: granular %s, dashpot %s (medians); granular/dashpot pair ratios:%s; median %.2fx; Pair time ratios:%s; median %.2fx\n" "$ranks" "$mg" "$md" "$ratios" "$mr" "$pratios" "$mp"
done
