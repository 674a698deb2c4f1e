#!/bin/sh
# The vertex-count table of papers/meshing-of-surfaces/cdrr.md (issue 15): on every
# smooth catalog surface, how many vertices each method needs for a certified topology
# and how long it takes —
#   PV    Plantinga-Vegter (`--algo pv`, isotopic), boxes and vertices;
#   BO    Boissonnat-Oudot with psi = 0.099 x a certified reach bound
#         (`--algo bo --set size=reach --certify`; the weak-sample claim; within a
#         vertex budget of 150000 and 120 s);
#   CDRR  `--algo cdrr` (homeomorphic, topological ball property);
#   CGAL  Surface_mesher (angle 30, Manifold_tag, error 1e-6, seed 0) at facet radius
#         r = 0.5, 0.3, 0.2, 0.1, 0.05, 0.02 (distance r/10; x2 for the tanglecube),
#         the coarsest r whose output `certmesh certify` certifies (CGAL's time; the
#         certify time beside it; surface_mesher.cpp knows sphere, torus, genus2,
#         tanglecube, two-spheres and thin-torus).
# CGAL comes from Debian's libcgal-dev (apt-get install -y libcgal-dev), never a
# dependency of the cargo build. Times are wall-clock seconds of one run on a shared
# machine.
#
# usage: benches/cgal/cdrr_table.sh [OUTDIR] [SURFACES]
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-/tmp/certmesh-cdrr-table}
surfaces=${2:-"sphere ellipsoid torus genus2 genus5 tanglecube two-spheres thin-torus paraboloid-cap blob superquadric"}
mkdir -p "$out"
[ -x "$out/surface_mesher" ] || g++ -O3 -DNDEBUG -std=c++17 -o "$out/surface_mesher" "$here/surface_mesher.cpp" -lgmp -lmpfr
(cd "$root" && cargo build --release --bin certmesh)
cm="${CARGO_TARGET_DIR:-$root/target}/release/certmesh"
row() { # label, then certmesh JSON on stdin -> "vertices seconds certified topology_ok extra"
    python3 -c 'import json,sys; d=json.load(sys.stdin); s=d.get("stats") or {}
extra = "boxes=%s" % s.get("leaves", s.get("boxes", "?")) if sys.argv[1] == "pv" else ""
print(sys.argv[1], d.get("vertices"), "%.3f" % d.get("seconds", 0), d.get("certified"), d.get("topology_ok"), extra,
      repr((d.get("reason") or "")[:90]))' "$1"
}
echo "| surface | method | vertices | seconds | certified | topology ok | note |"
for s in $surfaces; do
    sc=1; [ "$s" = tanglecube ] && sc=2
    "$cm" mesh "$s" --algo pv --json -q -o "$out/$s-pv.obj" | row pv | sed "s/^/$s /"
    timeout 300 "$cm" mesh "$s" --algo bo --set size=reach --certify --manifold --max-vertices 150000 --time-limit 120 \
        --json -q -o "$out/$s-bo.obj" | row bo-reach | sed "s/^/$s /" || echo "$s bo-reach - - timeout"
    "$cm" mesh "$s" --algo cdrr --json -q -o "$out/$s-cdrr.obj" | row cdrr | sed "s/^/$s /"
    case $s in sphere|torus|genus2|tanglecube|two-spheres|thin-torus) ;; *) echo "$s cgal: not in surface_mesher.cpp"; continue ;; esac
    found=""
    for r in 0.5 0.3 0.2 0.1 0.05 0.02; do
        rr=$(echo "$r*$sc" | bc -l); dd=$(echo "$r*$sc/10" | bc -l)
        line=$("$out/surface_mesher" "$s" 30 "$rr" "$dd" 0 "$out/$s-cgal-$r.off" 2>&1 | tail -1)
        c=$("$cm" certify "$out/$s-cgal-$r.off" --surface "$s" --json -q | python3 -c 'import json,sys; d=json.load(sys.stdin)
print(d["homeomorphic"], d["sample_points"], "%.3f" % d["seconds"], d["tbp"]["edge_failures"], d["tbp"]["manifold_failures"], d["tbp"]["facet_failures"], d["tbp"]["cell_failures"], d["is_rdt"])')
        echo "$s cgal r=$rr: $line | certify: $c"
        case $c in True*) found=$r; break ;; esac
    done
    [ -n "$found" ] || echo "$s cgal: no level certified"
done
