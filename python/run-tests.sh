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
# pytest runs in python/, where `import certmesh` finds the source package first: give
# it the extension module the install just built (the same file as in site-packages).
so="$("$venv/bin/python" -c '
import glob, os, site
for d in site.getsitepackages():
    for f in glob.glob(os.path.join(d, "certmesh", "_certmesh*.so")):
        print(f)
' | head -n 1)"
[ -n "$so" ] || { echo "run-tests.sh: the installed extension module was not found" >&2; exit 1; }
cp "$so" "$here/certmesh/"
cd "$here"
"$venv/bin/python" -m pytest -q "$@"
