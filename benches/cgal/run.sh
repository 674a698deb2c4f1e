#!/bin/sh
# CGAL anchor for the certmesh Delaunay kernel (issue 14). Builds benches/cgal/delaunay3.cpp
# against Debian's CGAL (apt-get install -y libcgal-dev; header-only, needs libgmp and
# libmpfr) — CGAL is never a dependency of the cargo build — writes the benchmark's
# point sets with examples/delaunay.rs (same samplers and seed as benches/delaunay.rs),
# and times both programs on each set, one after the other, with /usr/bin/time -v for
# the maximum resident set size. Each program prints its own in-process construction
# time and points/s.
#
# usage: benches/cgal/run.sh [OUTDIR]      (default /tmp/certmesh-delaunay-cgal)
set -eu
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
out=${1:-/tmp/certmesh-delaunay-cgal}
mkdir -p "$out"
g++ -O3 -DNDEBUG -std=c++17 -o "$out/delaunay3" "$here/delaunay3.cpp" -lgmp -lmpfr
(cd "$root" && cargo build --release --example delaunay)
ex="${CARGO_TARGET_DIR:-$root/target}/release/examples/delaunay"
for set in "uniform 100000 1e5" "sphere 100000 1e5" "uniform 1000000 1e6"; do
    set -- $set
    f="$out/$1-$3.bin"
    [ -f "$f" ] || "$ex" write "$2" "$1" 1 "$f"
    for prog in "$ex run" "$out/delaunay3"; do
        if [ -x /usr/bin/time ]; then
            /usr/bin/time -f "  max RSS %M KB, user %U s, wall %e s" $prog "$f"
        else
            $prog "$f"
        fi
    done
done
