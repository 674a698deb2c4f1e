"""Type stubs of the compiled module (python/src/lib.rs). Use the wrappers in
``certmesh`` and ``certmesh.proofs``; these are their building blocks."""
from typing import Any, Callable, Dict, List, Optional, Sequence

import numpy as np
import numpy.typing as npt

__version__: str

class CertmeshError(ValueError): ...

Progress = Optional[Callable[[str, int, int], Any]]

def mesh(
    dim: int,
    algo: str,
    surface: Optional[str] = None,
    formula: Optional[str] = None,
    function: Optional[Callable[..., Any]] = None,
    domain: Optional[Sequence[float]] = None,
    options: str = "{}",
    report: bool = True,
    metrics: str = "fast",
    progress: Progress = None,
) -> Dict[str, Any]: ...
def write_mesh(
    path: str,
    points: npt.NDArray[np.float64],
    cells: npt.NDArray[np.int64],
    boundary_points: Optional[npt.NDArray[np.float64]] = None,
    boundary_faces: Optional[npt.NDArray[np.int64]] = None,
) -> None: ...
def stats(
    points: npt.NDArray[np.float64],
    faces: npt.NDArray[np.int64],
    surface: Optional[str] = None,
    formula: Optional[str] = None,
) -> str: ...
def compare_runs(
    surfaces: List[str], algos: List[str], options: str = "{}", progress: Progress = None
) -> str: ...
def morse(
    surface: Optional[str] = None,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    height: Optional[Sequence[float]] = None,
    max_boxes: Optional[int] = None,
) -> str: ...
def certify(
    points: npt.NDArray[np.float64],
    faces: npt.NDArray[np.int64],
    surface: Optional[str] = None,
    formula: Optional[str] = None,
    domain: Optional[Sequence[float]] = None,
    max_boxes: Optional[int] = None,
) -> Dict[str, Any]: ...
def catalog() -> str: ...
def algorithms() -> str: ...
def option_names() -> List[str]: ...
def gradnormal_proof(
    a: str = "sommerville",
    rule: str = "paper",
    tol_deg: float = 1e-6,
    max_boxes: Optional[int] = None,
    time_limit: Optional[float] = None,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def stuffing_proof(
    row: Optional[str] = None,
    alpha_long: Optional[str] = None,
    alpha_short: Optional[str] = None,
    ordered: bool = False,
    side: str = "both",
    tol_deg: float = 1e-4,
    max_boxes: Optional[int] = None,
    time_limit: Optional[float] = None,
    progress: Progress = None,
) -> Dict[str, Any]: ...
def check_certificate(path: str) -> str: ...
