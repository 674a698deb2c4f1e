"""The Python package against the command line and against itself."""
import json
import os
import signal
import subprocess
import sys
import textwrap

import numpy as np
import pytest

import certmesh
from certmesh import CertmeshError


@pytest.mark.parametrize(
    "args, kw",
    [
        (("sphere", "--algo", "pv"), dict(surface="sphere", algo="pv")),
        (("torus", "--algo", "mc", "--resolution", "20"), dict(surface="torus", algo="mc", resolution=20)),
        (
            ("--formula", "x^4 + y^4 + z^4 - 1", "--algo", "snyder", "--max-depth", "6"),
            dict(formula="x^4 + y^4 + z^4 - 1", algo="snyder", max_depth=6),
        ),
        (("sphere", "--algo", "stuffing", "--resolution", "8"), dict(surface="sphere", algo="stuffing", resolution=8)),
    ],
)
def test_arrays_match_the_command_line(cli, tmp_path, args, kw):
    out = tmp_path / ("m.vtk" if kw["algo"] == "stuffing" else "m.obj")
    rep = cli("mesh", *args, "-o", str(out))
    r = certmesh.mesh(**kw, progress=False)
    assert r.report["vertices"] == rep["vertices"] == len(r.points if r.kind == "surface" else r.boundary_points)
    assert r.report["faces"] == rep["faces"]
    assert r.certificate == rep["certificate"]
    assert r.certified == (rep["certificate"]["status"] == "certified")
    assert r.report["found"] == rep["found"]
    if r.kind == "volume":
        assert r.report["tetrahedra"] == rep["tetrahedra"] == len(r.tets)
        assert r.tets.dtype == np.int64 and r.tets.shape[1] == 4
    else:
        assert r.faces.shape == (rep["faces"], 3) and r.faces.dtype == np.int64
        assert r.points.dtype == np.float64 and r.points.flags["C_CONTIGUOUS"]
        # The same mesh as the file the CLI wrote.
        import meshio

        m = meshio.read(out)
        np.testing.assert_allclose(m.points, r.points, rtol=0, atol=1e-9)
        assert (m.cells_dict["triangle"] == r.faces).all()


def test_curve_matches_the_command_line(cli, tmp_path):
    rep = cli("curve", "cassini-2", "--algo", "snyder", "-o", str(tmp_path / "c.csv"))
    c = certmesh.curve("cassini-2", algo="snyder", progress=False)
    assert c.kind == "curve" and c.points.shape[1] == 2 and c.segments.shape[1] == 2
    assert c.report["vertices"] == rep["vertices"] == len(c.points)
    assert c.report["faces"] == rep["faces"] == len(c.segments)
    assert c.certificate == rep["certificate"]


def test_meshio_round_trip(tmp_path):
    import meshio

    r = certmesh.mesh("torus", algo="mc", resolution=16, progress=False)
    m = r.to_meshio()
    p = tmp_path / "t.vtu"
    m.write(p)
    back = meshio.read(p)
    np.testing.assert_array_equal(back.points, r.points)
    np.testing.assert_array_equal(back.cells_dict["triangle"], r.faces)
    # and the project's own writers, read back by meshio
    for ext in ("obj", "ply", "off", "stl"):
        q = tmp_path / f"t.{ext}"
        r.write(q)
        m2 = meshio.read(q)
        assert len(m2.cells_dict["triangle"]) == len(r.faces)
    v = certmesh.mesh("sphere", algo="stuffing", resolution=6, progress=False)
    v.write(tmp_path / "s.vtk")
    assert len(meshio.read(tmp_path / "s.vtk").cells_dict["tetra"]) == len(v.tets)
    assert v.to_meshio().cells_dict["tetra"].shape == v.tets.shape


def test_vectorised_callback_gives_the_formulas_mesh():
    calls = []

    def f(x, y, z):
        calls.append(len(x))
        return x**2 + y**2 + z**2 - 0.8

    a = certmesh.mesh(f, domain=(-1, -1, -1, 1, 1, 1), algo="mc", resolution=24, crossing="linear", report=False, progress=False)
    b = certmesh.mesh(formula="x^2 + y^2 + z^2 - 0.8", domain=(-1, -1, -1, 1, 1, 1), algo="mc", resolution=24, crossing="linear", progress=False)
    np.testing.assert_allclose(a.points, b.points, rtol=0, atol=1e-12)
    np.testing.assert_array_equal(a.faces, b.faces)
    # the mesher calls it on whole batches (rows of the grid), not one point at a time
    assert min(calls) == max(calls) == 25 and len(calls) == 25 * 25


@pytest.mark.parametrize("algo", ["mc", "pv", "snyder", "gradnormal", "stuffing"])
def test_a_python_function_is_never_certified(algo):
    r = certmesh.mesh(
        lambda x, y, z: x * x + y * y + z * z - 1,
        algo=algo,
        progress=False,
        **({"max_depth": 3} if algo in ("pv", "snyder") else {"resolution": 8}),
    )
    assert not r.certified
    assert r.certificate["status"] == "uncertified"
    assert not any("isotopic" in c for c in r.claims)


def test_errors_raise_with_the_messages():
    with pytest.raises(CertmeshError, match="column"):
        certmesh.mesh(formula="x^2 + (y", algo="mc")
    with pytest.raises(CertmeshError, match="unknown option 'resolutoin'"):
        certmesh.mesh("sphere", algo="mc", resolutoin=8)
    with pytest.raises(CertmeshError, match="empty"):
        certmesh.mesh("sphere", algo="mc", domain=(0, 0, 0, 1, 0, 1))
    with pytest.raises(CertmeshError, match="needs 6 numbers"):
        certmesh.mesh("sphere", algo="mc", domain=(0, 0, 1, 1))
    with pytest.raises(CertmeshError):
        certmesh.mesh("no-such-surface", algo="mc")
    with pytest.raises(CertmeshError, match="algorithm"):
        certmesh.mesh("sphere", algo="no-such-algo")
    with pytest.raises(CertmeshError, match="not both|one of"):
        certmesh.mesh("sphere", formula="x", algo="mc")
    assert issubclass(CertmeshError, ValueError)


def test_an_exception_in_the_function_propagates():
    class Boom(RuntimeError):
        pass

    def f(x, y, z):
        raise Boom("from the user's function")

    with pytest.raises(Boom, match="user's function"):
        certmesh.mesh(f, algo="mc", resolution=8, progress=False)
    with pytest.raises(ValueError, match="one value per point"):
        certmesh.mesh(lambda x, y, z: np.zeros((len(x), 2)), algo="mc", resolution=8, progress=False)


def test_stats_surfaces_algorithms_compare_morse():
    names = [s["name"] for s in certmesh.surfaces()]
    assert "torus" in names and "sphere" in names
    assert all(c["dim"] == 2 for c in certmesh.curves())
    algos = {a["name"]: a for a in certmesh.algorithms()}
    assert algos["pv"]["certifying"] and not algos["mc"]["certifying"]
    r = certmesh.mesh("torus", algo="mc", resolution=20, progress=False)
    s = certmesh.stats(r.points, r.faces, surface="torus")
    assert s["topology_verdict"]["ok"] and s["genus"] == [1]
    # a wrong mesh gets the wrong verdict: drop half the faces
    s2 = certmesh.stats(r.points, r.faces[: len(r.faces) // 2], surface="torus")
    assert not s2["topology_verdict"]["ok"]
    with pytest.raises(CertmeshError, match="out of range"):
        certmesh.stats(r.points, r.faces + len(r.points))
    rows = certmesh.compare(["sphere", "torus"], ["mc", "pv"], resolution=16, dataframe=False, progress=False)
    assert [(x["surface"], x["algo"]) for x in rows] == [("sphere", "mc"), ("sphere", "pv"), ("torus", "mc"), ("torus", "pv")]
    assert all(x["certified"] == (x["algo"] == "pv") for x in rows)
    m = certmesh.morse("torus")
    assert m["expected_chi"] == 0


def test_without_report_the_run_is_the_same_mesh():
    a = certmesh.mesh("sphere", algo="pv", progress=False)
    b = certmesh.mesh("sphere", algo="pv", report=False, progress=False)
    np.testing.assert_array_equal(a.points, b.points)
    assert a.certificate == b.certificate and b.evaluations > 0 and b.seconds >= 0
    c = certmesh.mesh("sphere", algo="pv", metrics="none", progress=False)
    assert c.certificate == a.certificate and c.report["vertices"] == a.report["vertices"]
    with pytest.raises(CertmeshError, match="metrics|none"):
        certmesh.mesh("sphere", algo="pv", metrics="everything")


def test_progress_callback_sees_phases():
    seen = []
    certmesh.mesh("torus", algo="mc", resolution=160, progress=lambda p, d, t: seen.append((p, d, t)))
    # the run may be too fast for the 50 ms poll to see anything; when it does, the
    # phases are the mesher's
    assert all(isinstance(p, str) and d >= 0 for p, d, _ in seen)


@pytest.mark.parametrize("what", ["mesh", "proof"])
def test_ctrl_c_stops_a_long_run(what):
    code = textwrap.dedent(
        """
        import signal, sys, time, certmesh
        # A shell without job control starts background jobs with SIGINT ignored, and
        # Python then installs no KeyboardInterrupt handler: restore it, as a terminal has.
        signal.signal(signal.SIGINT, signal.default_int_handler)
        print("start", flush=True)
        t = time.time()
        try:
            if sys.argv[1] == "mesh":
                certmesh.mesh("sphere", algo="pv", min_depth=9, max_depth=10, max_boxes=10**9, progress=False)
            else:
                certmesh.proofs.stuffing(row="min-dihedral-double", tol_deg=1e-4, progress=False)
            print("finished", flush=True)
        except KeyboardInterrupt:
            print("interrupted after %.1f s" % (time.time() - t), flush=True)
        """
    )
    p = subprocess.Popen([sys.executable, "-c", code, what], stdout=subprocess.PIPE, text=True)
    assert p.stdout.readline().strip() == "start"
    import time

    time.sleep(1.5)
    p.send_signal(signal.SIGINT)
    out, _ = p.communicate(timeout=30)
    assert out.startswith("interrupted"), out
    # a mesh stops at its next evaluation of f; a proof at its next box, after its
    # case set-up (seconds on a loaded machine)
    assert float(out.split()[2]) < (10 if what == "mesh" else 40)


def test_proofs_stuffing_and_check(tmp_path):
    from certmesh import proofs

    r = proofs.stuffing(row="max-exposed-safe", tol_deg=5, progress=False)
    assert r.checked["complete"] and r.bounds[0]["verdict"] == "proven"
    lo, hi = r.bounds[0]["deg"]
    assert lo <= r.bounds[0]["paper"] + 1e-3 and hi - lo <= 5
    p = tmp_path / "c.json"
    r.write(p)
    assert certmesh.proofs.check(p)["ok"]
    # a tampered certificate is rejected
    c = json.loads(p.read_text())
    c["bounds"][0]["cos"][0] -= 0.01
    p.write_text(json.dumps(c))
    with pytest.raises(CertmeshError):
        certmesh.proofs.check(p)
    with pytest.raises(CertmeshError, match="alpha"):
        proofs.stuffing(alpha_long="0.6", alpha_short="0.4")
    with pytest.raises(CertmeshError, match="row"):
        proofs.stuffing(row="no-such-row")


def test_proofs_gradnormal():
    from certmesh import proofs

    r = proofs.gradnormal(tol_deg=0.01, progress=False)
    verdicts = {c["claim"]: c["verdict"] for c in r.claims}
    # the paper's 101.5° upper bound is refuted (the true supremum is arccos(-1/5))
    assert any("101.5" in k and v == "refuted" for k, v in verdicts.items()), verdicts
    with pytest.raises(CertmeshError):
        proofs.gradnormal(a="10")
