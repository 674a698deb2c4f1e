#!/bin/sh
# Regenerate papers/BENCH.md (issue 20): build the release binary, then time every
# workload against its anchor, interleaved (scripts/bench.py). Needs python3 with
# numpy and scikit-image (pip install scikit-image numpy). BENCH_REPS=N sets the
# repetitions (default 5).
set -e
cd "$(dirname "$0")/.."
cargo build --release --bin certmesh
dir="${CARGO_TARGET_DIR:-target}"
if [ -d /usr/include/CGAL ] && command -v g++ >/dev/null; then
    mesh3="${TMPDIR:-/tmp}/certmesh-mesh3-sphere"
    g++ -O3 -DNDEBUG -std=c++17 -o "$mesh3" benches/cgal/mesh3_sphere.cpp -lgmp -lmpfr
    export CGAL_MESH3="$mesh3"
    CGAL_VERSION="$(dpkg-query -W -f '${Version}' libcgal-dev 2>/dev/null || true)"
    export CGAL_VERSION
fi
CERTMESH="$(cd "$dir" && pwd)/release/certmesh" exec python3 scripts/bench.py
