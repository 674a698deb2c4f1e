import json
import os
import shutil
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]


def certmesh_bin():
    """The command-line binary to compare with: $CERTMESH_BIN, else the release build."""
    b = os.environ.get("CERTMESH_BIN")
    if b:
        return b
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    for p in (target / "release" / "certmesh", target / "debug" / "certmesh"):
        if p.exists():
            return str(p)
    w = shutil.which("certmesh")
    if w:
        return w
    pytest.skip("the certmesh binary is not built (cargo build --release)")


@pytest.fixture
def cli():
    def run(*args):
        out = subprocess.run(
            [certmesh_bin(), *args, "--json"], capture_output=True, text=True, check=False
        )
        assert out.returncode == 0, out.stderr + out.stdout
        return json.loads(out.stdout)

    return run
