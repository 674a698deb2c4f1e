#!/usr/bin/env bash
# The Python package's tests on a fresh machine: a virtual environment, `pip install
# ./python` exactly as the README says (maturin comes from PyPI as the build backend),
# then pytest (the suite, the docstring examples, the example notebooks).
# Called by .ci/run. Set CERTMESH_VENV to reuse a virtual environment.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(dirname "$here")"
venv="${CERTMESH_VENV:-$here/.venv}"
py="${PYTHON:-python3}"
[ -x "$venv/bin/python" ] || "$py" -m venv "$venv"
"$venv/bin/python" -m pip install -q --disable-pip-version-check \
  pytest meshio pandas nbclient nbformat ipykernel matplotlib
# The README's install command. The build shares the repository's target folder.
export CARGO_TARGET_DIR="${CARGO_TARGET_DIR:-$repo/target}"
"$venv/bin/python" -m pip install -q --disable-pip-version-check "$here"
# The command-line binary the tests compare with (cargo test built it already in CI).
if [ -z "${CERTMESH_BIN:-}" ]; then
  (cd "$repo" && cargo build -q --bin certmesh)
  export CERTMESH_BIN="$CARGO_TARGET_DIR/debug/certmesh"
fi
cd "$here"
"$venv/bin/python" -m pytest -q "$@"
