#!/bin/sh
# CGAL's Surface_mesher beside certmesh's `--algo bo` (issue 14), interleaved, on the
# same formulas and criteria (angle 30; radius/distance 0.1/0.01, 0.05/0.005,
# 0.02/0.002, doubled for the tanglecube), CGAL with Manifold_tag, error bound 1e-6,
# seed 0; certmesh with --manifold, float mode and --certify. CGAL comes from Debian's
# libcgal-dev (apt-get install -y libcgal-dev), never a dependency of the cargo build.
# Then the seeding experiment: two-spheres at coarse criteria over CGAL seeds 0..9.
#
# usage: benches/cgal/surface.sh [OUTDIR] [LEVELS]   (default /tmp/certmesh-bo-cgal, "1 2 3")
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-/tmp/certmesh-bo-cgal}
levels=${2:-"1 2 3"}
mkdir -p "$out"
g++ -O3 -DNDEBUG -std=c++17 -o "$out/surface_mesher" "$here/surface_mesher.cpp" -lgmp -lmpfr
(cd "$root" && cargo build --release --bin certmesh)
cm="${CARGO_TARGET_DIR:-$root/target}/release/certmesh"
crit() { # level scale -> "radius distance"
    case $1 in
        1) echo "$(echo "0.1*$2" | bc -l) $(echo "0.01*$2" | bc -l)" ;;
        2) echo "$(echo "0.05*$2" | bc -l) $(echo "0.005*$2" | bc -l)" ;;
        3) echo "$(echo "0.02*$2" | bc -l) $(echo "0.002*$2" | bc -l)" ;;
    esac
}
summary() { # certmesh JSON on stdin -> one line
    python3 -c 'import json,sys; d=json.load(sys.stdin); s=d.get("stats") or {}
print("vertices", d["vertices"], "facets", d["faces"], "angles %.2f-%.2f" % (d["min_angle_deg"] or 0, d["max_angle_deg"] or 0),
      "chi", d["mesh_chi"], "found", repr(d["found"]), "seconds %.3f" % d["seconds"], "evals", d["evaluations"],
      "claims", len((d.get("certificate") or {}).get("claims") or []), "reason", repr((d.get("reason") or "")[:70]))'
}
for level in $levels; do
    for s in sphere torus genus2 tanglecube two-spheres thin-torus; do
        sc=1; [ "$s" = tanglecube ] && sc=2
        set -- $(crit "$level" "$sc")
        "$out/surface_mesher" "$s" 30 "$1" "$2" 0
        printf "certmesh %s 30 %s %s float    " "$s" "$1" "$2"
        "$cm" mesh "$s" --algo bo --manifold --facet-size "$1" --facet-distance "$2" --json -q | summary
        printf "certmesh %s 30 %s %s certify  " "$s" "$1" "$2"
        "$cm" mesh "$s" --algo bo --manifold --certify --facet-size "$1" --facet-distance "$2" --json -q | summary
    done
done
echo "# seeding: two-spheres, radius 0.3, distance 0.03"
for seed in 0 1 2 3 4 5 6 7 8 9; do
    "$out/surface_mesher" two-spheres 30 0.3 0.03 "$seed" "$out/two-spheres-$seed.off"
    printf "  components: "
    "$cm" stats "$out/two-spheres-$seed.off" --json | python3 -c 'import json,sys; print(json.load(sys.stdin)["components"])'
done
printf "certmesh two-spheres 30 0.3 0.03 float    "
"$cm" mesh two-spheres --algo bo --manifold --facet-size 0.3 --facet-distance 0.03 --json -q | summary
