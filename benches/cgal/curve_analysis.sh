#!/bin/sh
# CGAL's Curve_analysis_2 (Algebraic_kernel_d_2) beside `certmesh curve --algo gvn`
# (issue 16), interleaved, on the classical curves of the design note. CGAL analyses
# f(x + s·y, y) in certmesh's chosen frame s, so that the events (critical x-values of
# the discriminant) and the arcs (points per event fibre, branches left and right of
# each) compare one to one; the script checks they agree. CGAL comes from Debian's
# libcgal-dev and libmpfi-dev (apt-get install -y libcgal-dev libmpfi-dev), never a
# dependency of the cargo build.
#
# Times: CGAL's median of REPS in-process analyses (a fresh kernel each), and the
# median wall time of REPS runs of the certmesh command (process start, parsing,
# sweep, certificate and SVG output included), the two tools alternating.
#
# usage: [CERTMESH_BIN=…] benches/cgal/curve_analysis.sh [OUTDIR] [REPS]
#        (default /tmp/certmesh-gvn-cgal, 5)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-/tmp/certmesh-gvn-cgal}
reps=${2:-5}
mkdir -p "$out"
# CERTMESH_BIN=path skips the cargo build; an existing, newer harness is reused.
if [ ! "$out/curve_analysis" -nt "$here/curve_analysis.cpp" ]; then
    g++ -O3 -DNDEBUG -DCGAL_USE_MPFI -std=c++17 -o "$out/curve_analysis" "$here/curve_analysis.cpp" \
        -lmpfi -lmpfr -lgmp
fi
if [ -n "${CERTMESH_BIN:-}" ]; then
    cm=$CERTMESH_BIN
else
    (cd "$root" && cargo build --release --bin certmesh)
    cm="${CARGO_TARGET_DIR:-$root/target}/release/certmesh"
fi
printf '| curve | shear | certmesh events | CGAL events | arcs agree | certmesh (ms) | CGAL (ms) |\n'
printf '|---|---|---|---|---|---|---|\n'
while IFS='|' read -r name dom formula; do
    [ -z "$name" ] && continue
    cert="$out/$name.json"
    "$cm" curve --formula "$formula" --domain "$dom" --algo gvn --certificate "$cert" \
        -o "$out/$name.svg" -q >/dev/null
    # The certificate's integer polynomial and shear -> CGAL's input; its critical
    # events -> "m l,r l,r ..." lines to compare with CGAL's event lines.
    python3 - "$cert" "$out/$name.in" "$out/$name.ours" <<'EOF'
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
EOF
    ours_ms=""
    cgal_ms=""
    for r in $(seq "$reps"); do
        t0=$(date +%s%N)
        "$cm" curve --formula "$formula" --domain "$dom" --algo gvn -o "$out/$name.svg" -q >/dev/null
        t1=$(date +%s%N)
        ours_ms="$ours_ms $(( (t1 - t0) / 1000 ))"
        "$out/curve_analysis" 1 <"$out/$name.in" >"$out/$name.cgal"
        cgal_ms="$cgal_ms $(sed -n 's/^median_ms //p' "$out/$name.cgal")"
    done
    sed -n 's/^event [^ ]* //p' "$out/$name.cgal" >"$out/$name.theirs"
    # CGAL also reports events whose fibre holds only complex critical points (phantom
    # events, m arcs passing straight through); certmesh lists them too.
    agree=no
    cmp -s "$out/$name.ours" "$out/$name.theirs" && agree=yes
    med() { echo "$@" | tr ' ' '\n' | sed '/^$/d' | sort -g | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
    printf '| %s | %s | %s | %s | %s | %.1f | %.1f |\n' "$name" \
        "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["shear"])' "$cert")" \
        "$(wc -l <"$out/$name.ours")" "$(wc -l <"$out/$name.theirs")" "$agree" \
        "$(echo "$(med $ours_ms) / 1000" | bc -l)" "$(med $cgal_ms)"
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
CURVES
