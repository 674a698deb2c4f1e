"""The example notebooks run top to bottom, and what they print is what they claim."""
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


def run(name, tmp_path):
    nb = nbformat.read(EXAMPLES / name, as_version=4)
    for c in nb.cells:
        if c.cell_type == "code":
            c.outputs = []
    nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}}
    ).execute()
    text = []
    for c in nb.cells:
        for o in c.get("outputs", []):
            assert o.get("output_type") != "error", o
            text.append(o.get("text", "") + str(o.get("data", {}).get("text/plain", "")))
    return "\n".join(text)


def test_compare_notebook(tmp_path):
    out = run("compare-topology.ipynb", tmp_path)
    assert "proven right" in out
    # marching cubes never claims a proof
    assert "proven right" not in [l for l in out.splitlines() if l.startswith("mc")]


def test_figure_notebook(tmp_path):
    out = run("publication-figure.ipynb", tmp_path)
    assert (tmp_path / "angles-three-meshers.svg").stat().st_size > 1000
    assert (tmp_path / "angles-three-meshers.png").stat().st_size > 1000
    assert "'pv': (" in out and "True)" in out
