"""certmesh: certified meshing of implicit curves and surfaces f = 0, from numpy.

Every result says what was *proven* (by interval arithmetic with outward rounding, or
exact arithmetic) and what was not, with where and why::

    >>> import certmesh
    >>> r = certmesh.mesh("sphere", algo="pv")
    >>> r.certified, r.points.shape[1], r.faces.shape[1]
    (True, 3, 3)
    >>> r.certificate["claims"][0].startswith("isotopic")
    True

A formula string is meshed the same way (the default domain is [-2, 2]^3)::

    >>> r = certmesh.mesh(formula="x^2 + y^2 + z^2 - 1", algo="mc", resolution=16)
    >>> r.certified          # marching cubes is a baseline: it proves nothing
    False
    >>> r.stats["components"], r.stats["genus"]
    (1, [0])

A vectorised Python function works for the meshers that need no interval extension;
it is called on whole numpy arrays and is never certified::

    >>> import numpy as np
    >>> r = certmesh.mesh(lambda x, y, z: x**2 + y**2 + z**2 - 1, algo="mc", resolution=16)
    >>> r.certified, r.certificate["status"]
    (False, 'uncertified')

Errors are :class:`CertmeshError` (a ``ValueError``) with the command line's message::

    >>> certmesh.mesh(formula="x^2 + (y", algo="mc")
    Traceback (most recent call last):
    ...
    certmesh.CertmeshError: formula error: expected ')' but the formula ended at column 9

Long runs release the GIL and stop on Ctrl-C (``KeyboardInterrupt``); progress is shown
with ``tqdm`` when it is installed and the output is a terminal or a notebook
(``progress=False`` turns it off, ``progress=True`` forces it, or pass a callable
``progress(phase, done, total)``).
"""
from __future__ import annotations

import json as _json
from dataclasses import dataclass, field
from typing import Any, Callable, Dict, List, Optional, Sequence, Union

import numpy as np

from . import _certmesh
from ._certmesh import CertmeshError, __version__
from . import proofs

__all__ = [
    "CertmeshError",
    "MeshResult",
    "algorithms",
    "certify",
    "compare",
    "curve",
    "curves",
    "mesh",
    "morse",
    "proofs",
    "stats",
    "surfaces",
    "__version__",
]


def _progress(progress: Any) -> Optional[Callable[[str, int, int], None]]:
    """A callback (phase, done, total) drawing a tqdm bar, or None."""
    if progress is False or progress is None:
        return None
    if callable(progress):
        return progress
    if progress == "auto":
        import sys

        interactive = "ipykernel" in sys.modules or (
            hasattr(sys.stderr, "isatty") and sys.stderr.isatty()
        )
        if not interactive:
            return None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None
    state: Dict[str, Any] = {"bar": None, "phase": None}

    def cb(phase: str, done: int, total: int) -> None:
        if phase != state["phase"]:
            if state["bar"] is not None:
                state["bar"].close()
            state["bar"] = tqdm(total=total or None, desc=phase, leave=False)
            state["phase"] = phase
        bar = state["bar"]
        bar.n = done
        bar.refresh()

    cb.close = lambda: state["bar"] is not None and state["bar"].close()  # type: ignore[attr-defined]
    return cb


def _close(cb: Any) -> None:
    close = getattr(cb, "close", None)
    if close is not None:
        close()


@dataclass
class MeshResult:
    """One mesher run: the arrays, the certificate and the report.

    ``points`` is (N, 3) float64 ((N, 2) for curves); exactly one of ``faces`` (M, 3),
    ``tets`` (M, 4) and ``segments`` (M, 2) int64 is set, by ``kind``. A volume mesh
    also carries its boundary surface (``boundary_points``, ``boundary_faces``).
    ``report`` is the document ``certmesh mesh --json`` prints (topology verdict,
    angles, Hausdorff estimate, certificate, mesher statistics, evaluation counts).
    """

    kind: str
    points: np.ndarray
    report: Dict[str, Any]
    faces: Optional[np.ndarray] = None
    tets: Optional[np.ndarray] = None
    segments: Optional[np.ndarray] = None
    boundary_points: Optional[np.ndarray] = None
    boundary_faces: Optional[np.ndarray] = None

    @property
    def certificate(self) -> Dict[str, Any]:
        """The typed certificate: ``status`` ("certified" or "uncertified"), ``claims``
        (what was proven), and for an uncertified run ``reason`` and ``regions``."""
        return self.report["certificate"]

    @property
    def certified(self) -> bool:
        """True only when every claim of the mesher was proven."""
        return self.certificate["status"] == "certified"

    @property
    def claims(self) -> List[str]:
        return list(self.certificate.get("claims", []))

    @property
    def stats(self) -> Dict[str, Any]:
        """The report without the certificate: topology found, angles, Hausdorff
        estimate, and the mesher's own statistics under ``"mesher"``."""
        s = {k: v for k, v in self.report.items() if k not in ("certificate", "stats")}
        s["mesher"] = self.report.get("stats", {})
        return s

    @property
    def seconds(self) -> float:
        """Wall time of the mesher itself (metrics not included)."""
        return float(self.report["seconds"])

    @property
    def evaluations(self) -> int:
        """Evaluations of f of every kind (``report["evaluation_counts"]`` by kind)."""
        return int(self.report["evaluations"])

    def cells(self) -> np.ndarray:
        for c in (self.faces, self.tets, self.segments):
            if c is not None:
                return c
        raise CertmeshError("the result has no cells")

    def write(self, path: str) -> None:
        """Write the mesh with certmesh's own writers; the format follows the extension
        (.obj .off .ply .stl for surfaces, .vtk .mesh for tetrahedra, .svg .csv for
        curves)."""
        _certmesh.write_mesh(
            str(path), self.points, self.cells(), self.boundary_points, self.boundary_faces
        )

    def to_meshio(self):
        """The mesh as a ``meshio.Mesh`` (meshio is imported on use)."""
        import meshio

        if self.kind == "curve":
            pts = np.column_stack([self.points, np.zeros(len(self.points))])
            return meshio.Mesh(pts, [("line", self.segments)])
        if self.kind == "volume":
            return meshio.Mesh(self.points, [("tetra", self.tets)])
        return meshio.Mesh(self.points, [("triangle", self.faces)])

    def __repr__(self) -> str:
        n = self.cells().shape[0]
        what = {"surface": "triangles", "volume": "tetrahedra", "curve": "segments"}[self.kind]
        status = "certified" if self.certified else "uncertified"
        return (
            f"<MeshResult {self.report.get('algo')} on {self.report.get('surface')}: "
            f"{len(self.points)} vertices, {n} {what}, {status}>"
        )


def _run(dim: int, surface, formula, domain, algo, report, metrics, progress, params) -> MeshResult:
    function = None
    if callable(surface):
        function, surface = surface, None
    elif surface is not None and not isinstance(surface, str):
        raise CertmeshError(
            "surface must be a catalog name (see certmesh.surfaces()) or a vectorised "
            "Python function f(x, y, z) of numpy arrays"
        )
    cb = _progress(progress)
    try:
        d = _certmesh.mesh(
            dim,
            algo,
            surface=surface,
            formula=formula,
            function=function,
            domain=None if domain is None else [float(x) for x in domain],
            options=_json.dumps(params),
            report=report,
            metrics=metrics,
            progress=cb,
        )
    finally:
        _close(cb)
    d["report"] = _json.loads(d["report"])
    return MeshResult(**d)


def mesh(
    surface: Union[str, Callable[..., Any], None] = None,
    *,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    algo: str = "mc",
    report: bool = True,
    metrics: str = "fast",
    progress: Any = "auto",
    **params: Any,
) -> MeshResult:
    """Mesh the surface f(x, y, z) = 0.

    surface: a catalog name (``certmesh.surfaces()``), or a vectorised Python function
        ``f(x, y, z)`` taking numpy arrays (uncertified: it has no interval extension).
    formula: f as text in certmesh's formula language, e.g. ``"x^2 + y^2 + z^2 - 1"``.
    domain: ``(x0, y0, z0, x1, y1, z1)``; default: the catalog's box, or [-2, 2]^3.
    algo: ``mc``, ``mt``, ``pv``, ``snyder``, ``gradnormal``, ``midnormal``,
        ``stuffing``, ``bo``, ... (``certmesh.algorithms()``).
    report: compute the report (topology, angles, Hausdorff estimate); False returns
        the mesh, the certificate and the mesher's statistics only.
    metrics: the report's measures, as the command line's ``--metrics``: ``"fast"``
        (default; the fields of ``"full"``, with the Hausdorff estimate's mesh side
        from area-proportional samples only, not every vertex, and on a mesh under
        640,000 triangles a sample sized to it, about one mesh sample per 32
        triangles refined on the triangles of the largest distances, and a coarser
        seed grid: labelled by ``hausdorff_kind`` and the
        sample counts), ``"full"``, or
        ``"none"`` (sizes, time and certificate only).
    **params: the mesher's options by name (``resolution=64``, ``max_depth=8``,
        ``facet_angle=30``, ...; ``certmesh._certmesh.option_names()``), and
        ``settings={key: value}`` for algorithm-specific settings.

    >>> r = certmesh.mesh("torus", algo="mc", resolution=24)
    >>> r.kind, r.stats["genus"]
    ('surface', [1])
    """
    return _run(3, surface, formula, domain, algo, report, metrics, progress, params)


def curve(
    surface: Union[str, Callable[..., Any], None] = None,
    *,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    algo: str = "pv",
    report: bool = True,
    metrics: str = "fast",
    progress: Any = "auto",
    **params: Any,
) -> MeshResult:
    """Mesh the curve f(x, y) = 0: polylines as ``points`` (N, 2) and ``segments``
    (M, 2). Same arguments as :func:`mesh`; the domain is ``(x0, y0, x1, y1)``.

    >>> c = certmesh.curve(formula="x^2 + 4*y^2 - 1", domain=(-1.5, -1, 1.5, 1), algo="pv")
    >>> c.kind, c.points.shape[1], c.certified
    ('curve', 2, True)
    """
    return _run(2, surface, formula, domain, algo, report, metrics, progress, params)


def stats(points, faces, *, surface: Optional[str] = None, formula: Optional[str] = None):
    """Quality, topology and (with a surface) fidelity of any triangle mesh, as
    ``certmesh stats --json`` reports them.

    >>> r = certmesh.mesh("sphere", algo="mc", resolution=12)
    >>> s = certmesh.stats(r.points, r.faces, surface="sphere")
    >>> s["topology_verdict"]["ok"]
    True
    """
    p = np.ascontiguousarray(points, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    return _json.loads(_certmesh.stats(p, f, surface=surface, formula=formula))


def _entries() -> List[Dict[str, Any]]:
    return _json.loads(_certmesh.catalog())


def surfaces() -> List[Dict[str, Any]]:
    """The catalog's surfaces: name, formula, domain, expected topology, smoothness.

    >>> "torus" in [s["name"] for s in certmesh.surfaces()]
    True
    """
    return [e for e in _entries() if e["dim"] == 3]


def curves() -> List[Dict[str, Any]]:
    """The catalog's curves."""
    return [e for e in _entries() if e["dim"] == 2]


def algorithms() -> List[Dict[str, Any]]:
    """The registered meshers: name, dimension, whether they certify, what they read."""
    return _json.loads(_certmesh.algorithms())


def compare(
    surfaces: Sequence[str],
    algos: Sequence[str],
    *,
    dataframe: Optional[bool] = None,
    progress: Any = "auto",
    **params: Any,
):
    """Run every algorithm on every catalog surface and judge the outputs side by side
    (``certmesh compare --json``): one record per run, with the topology verdict,
    angles, Hausdorff estimate, time, evaluations and certificate. Returns a pandas
    DataFrame when pandas is installed (``dataframe=False``: always a list of dicts).

    >>> rows = certmesh.compare(["sphere"], ["mc", "pv"], resolution=12, dataframe=False)
    >>> [(r["algo"], r["certified"]) for r in rows]
    [('mc', False), ('pv', True)]
    """
    cb = _progress(progress)
    try:
        rows = _json.loads(
            _certmesh.compare_runs(list(surfaces), list(algos), _json.dumps(params), cb)
        )
    finally:
        _close(cb)
    if dataframe is False:
        return rows
    try:
        import pandas as pd
    except ImportError:
        if dataframe:
            raise
        return rows
    return pd.DataFrame(rows)


def morse(
    surface: Optional[str] = None,
    *,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    height: Optional[Sequence[float]] = None,
    max_boxes: Optional[int] = None,
) -> Dict[str, Any]:
    """The certified Morse census of f (``certmesh morse --json``): the critical points
    of f and of a height function on S, each in an existence-and-uniqueness box with a
    certified index, and the Euler characteristic when everything was decided.

    >>> m = certmesh.morse("sphere")
    >>> m["chi"], m["expected_chi"]
    (2, 2)
    """
    return _json.loads(
        _certmesh.morse(
            surface=surface,
            formula=formula,
            domain=None if domain is None else [float(x) for x in domain],
            height=None if height is None else [float(x) for x in height],
            max_boxes=max_boxes,
        )
    )


def certify(
    points,
    faces,
    *,
    surface: Optional[str] = None,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    max_boxes: Optional[int] = None,
) -> Dict[str, Any]:
    """Certify anyone's triangle mesh against f = 0 (``certmesh certify --json``): is it
    the restricted Delaunay triangulation of its vertices, and does the topological ball
    property hold (Boissonnat et al., *Meshing of Surfaces*, 2007, §1.3.2, Theorem 5)?
    ``homeomorphic`` is True only when both were proven. The certified restricted
    Delaunay triangulation comes back as ``rdt_points`` and ``rdt_faces``.

    >>> r = certmesh.mesh("sphere", algo="bo", facet_angle=25, facet_size=0.3, facet_distance=0.02)
    >>> c = certmesh.certify(r.points, r.faces, surface="sphere")
    >>> isinstance(c["homeomorphic"], bool), c["verdict"] != ""
    (True, True)
    """
    p = np.ascontiguousarray(points, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    d = _certmesh.certify(
        p,
        f,
        surface=surface,
        formula=formula,
        domain=None if domain is None else [float(x) for x in domain],
        max_boxes=max_boxes,
    )
    rep = _json.loads(d["report"])
    rep["rdt_points"], rep["rdt_faces"] = d["points"], d["faces"]
    return rep
