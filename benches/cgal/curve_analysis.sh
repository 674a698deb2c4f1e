#!/bin/sh
# CGAL's Curve_analysis_2 (Algebraic_kernel_d_2) beside certmesh's exact sweep
# (`--algo gvn`, issue 16), in one run, on the classical curves of the design note and
# on dense random curves. CGAL analyses f(x + s·y, y) in certmesh's chosen frame s, so
# that the events (critical x-values of the discriminant) and the arcs (points per
# event fibre, branches left and right of each) compare one to one; the script checks
# they agree on the classical curves. CGAL comes from Debian's libcgal-dev and
# libmpfi-dev (apt-get install -y libcgal-dev libmpfi-dev), never a dependency of the
# cargo build.
#
# Times, both in process, the analysis only: certmesh's median of REPS runs of
# `sweep::analyse` (examples/gvn_time.rs: shear retries included, no process start,
# parsing, certificate or SVG) and CGAL's median of REPS analyses (a fresh kernel each,
# every event and interval status line forced). The two alternate ROUNDS times per
# curve (A B A B ...); the table gives the median over the rounds of each, their ratio
# certmesh / CGAL, and the 1-minute load average at the end of the curve.
#
# The dense random curves (coefficients in [-10, 10], the generator and seeds of
# benches/algebraic.rs) are analysed by certmesh inside the box ±2 only (events and
# arcs outside it are not computed), by CGAL in the whole plane, so their events are
# not compared and their ratio favours certmesh.
#
# GVN_TIME_BIN_OLD=path (optional): a second gvn_time binary (an older build) timed in
# the same rounds (A B C A B C ...), as an extra column "before (ms)" and its ratio.
#
# usage: [GVN_TIME_BIN=…] [GVN_TIME_BIN_OLD=…] benches/cgal/curve_analysis.sh [OUTDIR] [REPS] [ROUNDS]
#        (default /tmp/certmesh-gvn-cgal, 5, 3)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-/tmp/certmesh-gvn-cgal}
reps=${2:-5}
rounds=${3:-3}
mkdir -p "$out"
if [ ! "$out/curve_analysis" -nt "$here/curve_analysis.cpp" ]; then
    g++ -O3 -DNDEBUG -DCGAL_USE_MPFI -std=c++17 -o "$out/curve_analysis" "$here/curve_analysis.cpp" \
        -lmpfi -lmpfr -lgmp
fi
# GVN_TIME_BIN=path skips the cargo build.
if [ -n "${GVN_TIME_BIN:-}" ]; then
    cm=$GVN_TIME_BIN
else
    (cd "$root" && cargo build --release --example gvn_time)
    cm="${CARGO_TARGET_DIR:-$root/target}/release/examples/gvn_time"
fi
med() { echo "$@" | tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
old=${GVN_TIME_BIN_OLD:-}
if [ -n "$old" ]; then
    printf '| curve | shear | certmesh events | CGAL events | arcs agree | before (ms) | certmesh (ms) | CGAL (ms) | before / CGAL | certmesh / CGAL | load |\n'
    printf '|---|---|---|---|---|---|---|---|---|---|---|\n'
else
    printf '| curve | shear | certmesh events | CGAL events | arcs agree | certmesh (ms) | CGAL (ms) | certmesh / CGAL | load |\n'
    printf '|---|---|---|---|---|---|---|---|---|\n'
fi
while IFS='|' read -r name dom spec; do
    [ -z "$name" ] && continue
    cert="$out/$name.json"
    "$cm" "$spec" "$dom" 1 "$cert" >/dev/null
    # The certificate's integer polynomial and shear -> CGAL's input; its critical
    # events -> "m l,r l,r ..." lines to compare with CGAL's event lines.
    python3 - "$cert" "$out/$name.in" "$out/$name.ours" <<'PY'
import json, sys
c = json.load(open(sys.argv[1]))
with open(sys.argv[2], "w") as f:
    f.write("%d\n" % c["shear"])
    for j, row in enumerate(c["f"]):
        for i, a in enumerate(row):
            if int(a) != 0:
                f.write("%s %d %d\n" % (a, i, j))
with open(sys.argv[3], "w") as f:
    for e in c["events"]:
        if e["critical"]:
            f.write(" ".join([str(e["m"])] + ["%d,%d" % (r["left"], r["right"]) for r in e["roots"]]) + "\n")
PY
    ours_ms=""
    cgal_ms=""
    old_ms=""
    for r in $(seq "$rounds"); do
        if [ -n "$old" ]; then
            old_ms="$old_ms $("$old" "$spec" "$dom" "$reps" | sed -n 's/^median_ms //p')"
        fi
        ours_ms="$ours_ms $("$cm" "$spec" "$dom" "$reps" | sed -n 's/^median_ms //p')"
        "$out/curve_analysis" "$reps" <"$out/$name.in" >"$out/$name.cgal"
        cgal_ms="$cgal_ms $(sed -n 's/^median_ms //p' "$out/$name.cgal")"
    done
    sed -n 's/^event [^ ]* //p' "$out/$name.cgal" >"$out/$name.theirs"
    # CGAL also reports events whose fibre holds only complex critical points (phantom
    # events, m arcs passing straight through); certmesh lists them too.
    case "$spec" in
    dense:*) agree="– (box ±2)" ;;
    *) agree=no; cmp -s "$out/$name.ours" "$out/$name.theirs" && agree=yes ;;
    esac
    mo=$(med $ours_ms)
    mc=$(med $cgal_ms)
    sh_=$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["shear"])' "$cert")
    if [ -n "$old" ]; then
        mb=$(med $old_ms)
        printf '| %s | %s | %s | %s | %s | %.2f | %.2f | %.2f | %.2f | %.2f | %s |\n' "$name" "$sh_" \
            "$(wc -l <"$out/$name.ours")" "$(wc -l <"$out/$name.theirs")" "$agree" \
            "$mb" "$mo" "$mc" "$(echo "$mb / $mc" | bc -l)" "$(echo "$mo / $mc" | bc -l)" \
            "$(cut -d' ' -f1 /proc/loadavg)"
    else
        printf '| %s | %s | %s | %s | %s | %.2f | %.2f | %.2f | %s |\n' "$name" "$sh_" \
            "$(wc -l <"$out/$name.ours")" "$(wc -l <"$out/$name.theirs")" "$agree" \
            "$mo" "$mc" "$(echo "$mo / $mc" | bc -l)" "$(cut -d' ' -f1 /proc/loadavg)"
    fi
done <<'CURVES'
lemniscate|-2,-2,2,2|(x^2 + y^2)^2 - 2*(x^2 - y^2)
limacon|-2,-2,2,2|(x^2 + y^2 - x)^2 - (x^2 + y^2)/4
trifolium|-2,-2,2,2|(x^2 + y^2)^2 - (x^3 - 3*x*y^2)
quadrifolium|-2,-2,2,2|(x^2 + y^2)^3 - 4*x^2*y^2
tacnode|-2,-2,2,2|y^2 - x^4
devil|-3,-3,3,3|y^2*(y^2 - 1) - x^2*(x^2 - 2)
t4|-2,-2,2,2|8*x^4 - 8*x^2 + 8*y^4 - 8*y^2 + 2
cusp|-2,-2,2,2|y^2 - x^3
crunode|-2,-2,2,2|y^2 - x^2*(x + 1)
acnode|-2.5,-2.5,2.5,2.5|y^2 - x^2*(x - 1)
degree8-mix|-3,-3,3,3|((x^2 + y^2)^2 - 2*(x^2 - y^2))*(x^2 + y^2 - 4)*(x - y^2 + 1)
dense-d5|-2,-2,2,2|dense:5:12
dense-d6|-2,-2,2,2|dense:6:13
dense-d7|-2,-2,2,2|dense:7:14
dense-d8|-2,-2,2,2|dense:8:15
CURVES
