#!/usr/bin/env bash
# Switches a LAMMPS deck from LAMMPS's granular styles to dashpot's, one word each:
#   pair_style granular [cutoff]          -> pair_style dashpot [cutoff]
#   pair_style gran/X ARGS                -> pair_style dashpot gran/X ARGS
#   pair_style hybrid ... granular ...    -> pair_style hybrid ... dashpot ...
#     (and pair_coeff I J granular ...    -> pair_coeff I J dashpot ...)
#   fix ID G wall/gran granular ...       -> fix ID G wall/dashpot ...
#   fix ID G wall/gran/region granular ...-> fix ID G wall/dashpot/region ...
#   fix ID G wall/gran X ...              -> fix ID G wall/dashpot X ...     (X = hooke, ...)
#   fix ID G wall/gran/region X ...       -> fix ID G wall/dashpot/region X ...
# and loads the plugin before the first of them (plugin load PLUGIN). Every other line, the
# models' words and the deck's units, types and walls stay as they are.
#
#   examples/lammps/switch.sh [--plugin PATH] [--plugin-dir DIR] DECK > DECK.dashpot
#
# --plugin PATH    the plugin to load (default: dashpotplugin.so, found by LAMMPS's plugin path)
# --plugin-dir DIR appends plugin_dir=DIR to the dashpot styles (where the law plugins are;
#                  default: none, the styles then search $DASHPOT_PLUGIN_PATH)
# A line continued with '&' is switched if its first line names the style. The styles' /omp
# variants switch too (dashpot has none: gran/hooke/omp becomes dashpot gran/hooke).
set -euo pipefail
plugin="dashpotplugin.so"
plugin_dir=""
while [ $# -gt 1 ]; do
    case "$1" in
        --plugin) plugin="$2"; shift 2 ;;
        --plugin-dir) plugin_dir="$2"; shift 2 ;;
        *) echo "switch.sh: unknown option '$1' (valid: --plugin PATH, --plugin-dir DIR)" >&2; exit 2 ;;
    esac
done
[ $# -eq 1 ] || { echo "usage: switch.sh [--plugin PATH] [--plugin-dir DIR] DECK > DECK.dashpot" >&2; exit 2; }
deck="$1"
[ -r "$deck" ] || { echo "switch.sh: cannot read '$deck'" >&2; exit 1; }

awk -v plugin="$plugin" -v pdir="$plugin_dir" '
function load() {
    if (!loaded) { print "plugin load     " plugin; loaded = 1 }
}
function dir() { return pdir == "" ? "" : " plugin_dir=" pdir }
# the style word without an accelerator suffix
function base(s) { sub(/\/omp$/, "", s); return s }
{
    line = $0
    n = split(line, w, /[ \t]+/)
    first = (w[1] == "" && n > 1) ? 2 : 1
    cmd = w[first]
    if (cmd == "plugin" && w[first + 1] == "load") loaded = 1
    if (cmd == "pair_style") {
        style = base(w[first + 1])
        if (style == "granular") {
            load(); sub(/granular(\/omp)?/, "dashpot", line); print line dir(); next
        }
        if (style ~ /^gran\//) {
            load(); sub(/gran\/[a-z\/]*/, "dashpot " style, line); print line dir(); next
        }
        if (style ~ /^hybrid/ && line ~ /[ \t]granular([ \t]|$)/) {
            load(); gsub(/[ \t]granular([ \t]|$)/, " dashpot" dir() " ", line); print line; next
        }
    }
    if (cmd == "pair_coeff" && w[first + 3] == "granular") {
        sub(/[ \t]granular([ \t]|$)/, " dashpot ", line); print line; next
    }
    if (cmd == "fix" && (w[first + 3] == "wall/gran" || w[first + 3] == "wall/gran/region")) {
        load()
        region = w[first + 3] == "wall/gran/region"
        if (w[first + 4] == "granular")
            sub(/wall\/gran(\/region)?[ \t]+granular/, region ? "wall/dashpot/region" : "wall/dashpot", line)
        else
            sub(/wall\/gran(\/region)?/, region ? "wall/dashpot/region" : "wall/dashpot", line)
        print line dir(); next
    }
    print line
}' "$deck"
