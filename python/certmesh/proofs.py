"""The computer-assisted proofs of the ``proofs`` binary, from Python.

Each function runs the certified branch and bound (interval arithmetic with outward
rounding, exact rational comparisons), re-checks the certificate independently, and
returns a :class:`ProofResult` with the certificate (the same JSON document
``proofs ... --out`` writes, readable by ``proofs check``) and its summary.

>>> from certmesh import proofs
>>> r = proofs.gradnormal(tol_deg=0.01, progress=False)
>>> r.kind, r.checked["complete"]
('gradnormal', True)
>>> c = r.claims[0]
>>> c["claim"], c["verdict"]
('Lemma 4.1: MidNormal angles >= 45°', 'proven')

A Table 1 row of isosurface stuffing (about half a minute at 5°; the paper's
precision, ``tol_deg=1e-4``, takes minutes)::

    r = proofs.stuffing(row="max-exposed-safe", tol_deg=5)
    r.bounds[0]["bound"], r.bounds[0]["verdict"]   # ('min_dihedral', 'proven')
"""
from __future__ import annotations

import json as _json
from dataclasses import dataclass
from typing import Any, Dict, List, Optional

from . import _certmesh

__all__ = ["ProofResult", "gradnormal", "stuffing", "check"]


@dataclass
class ProofResult:
    """A proof run: ``certificate`` (dict), ``summary`` (dict), ``checked`` (the
    independent re-check's report)."""

    kind: str
    certificate: Dict[str, Any]
    summary: Any
    checked: Dict[str, Any]

    @property
    def bounds(self) -> List[Dict[str, Any]]:
        """Stuffing: the certified enclosure of each angle extreme beside the paper's
        value."""
        return list(self.checked.get("bounds", []))

    @property
    def claims(self) -> List[Dict[str, Any]]:
        """GradNormal: each claim of the paper with its verdict (confirmed/refuted)."""
        return list(self.checked.get("claims", []))

    def write(self, path: str) -> None:
        """Write the certificate (re-checkable with ``proofs check PATH`` or
        :func:`check`)."""
        with open(path, "w") as f:
            _json.dump(self.certificate, f)


def _progress(progress):
    from . import _progress as p

    return p(progress)


def _finish(d: Dict[str, Any]) -> ProofResult:
    return ProofResult(
        kind=d["kind"],
        certificate=_json.loads(d["certificate"]),
        summary=_json.loads(d["summary"]),
        checked=_json.loads(d["checked"]),
    )


def gradnormal(
    a: str = "sommerville",
    rule: str = "paper",
    *,
    tol_deg: float = 1e-6,
    max_boxes: Optional[int] = None,
    time_limit: Optional[float] = None,
    progress: Any = "auto",
) -> ProofResult:
    """The GradNormal angle bounds (Hass & Trnkova 2020, Appendix A): every triangle
    angle over every configuration of the tiling with ratio ``a`` and the diagonal
    ``rule`` ("paper", "alternate", "shorter"), enclosed to ``tol_deg``, and the
    paper's claims confirmed or refuted."""
    cb = _progress(progress)
    d = _certmesh.gradnormal_proof(a, rule, tol_deg, max_boxes, time_limit, cb)
    return _finish(d)


def stuffing(
    row: Optional[str] = None,
    *,
    alpha_long: Optional[str] = None,
    alpha_short: Optional[str] = None,
    ordered: bool = False,
    side: str = "both",
    tol_deg: float = 1e-4,
    max_boxes: Optional[int] = None,
    time_limit: Optional[float] = None,
    progress: Any = "auto",
) -> ProofResult:
    """The isosurface-stuffing dihedral and plane angle bounds (Labelle & Shewchuk
    2007, §4.1) of a Table 1 ``row`` or of any parameter pair (``alpha_long``,
    ``alpha_short`` as decimal strings, read exactly), with the safe-property verdict
    (a pair admitting flat tetrahedra gets that verdict and a witness, not a bound)."""
    cb = _progress(progress)
    d = _certmesh.stuffing_proof(
        row, alpha_long, alpha_short, ordered, side, tol_deg, max_boxes, time_limit, cb
    )
    return _finish(d)


def check(path: str) -> Dict[str, Any]:
    """Re-check a certificate file (GradNormal or stuffing) independently of the search
    that wrote it; raises CertmeshError naming the first field that differs."""
    return _json.loads(_certmesh.check_certificate(str(path)))
