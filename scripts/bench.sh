#!/bin/sh
# Regenerate papers/BENCH.md (issue 20): build the release binary, then time every
# workload against its anchor, interleaved (scripts/bench.py). Needs python3 with
# numpy and scikit-image (pip install scikit-image numpy). BENCH_REPS=N sets the
# repetitions (default 5).
set -e
cd "$(dirname "$0")/.."
cargo build --release --bin certmesh
dir="${CARGO_TARGET_DIR:-target}"
CERTMESH="$(cd "$dir" && pwd)/release/certmesh" exec python3 scripts/bench.py
