"""Time scikit-image's marching cubes on the same 256^3-cell torus volume as
benches/marching.rs (catalog `torus`, domain [-1, 1]^3, 257^3 vertices, float64).

    pip install scikit-image
    python3 benches/skimage_mc.py          # several runs, readable
    python3 benches/skimage_mc.py --once   # one run, JSON (scripts/bench.py)

Prints the best and median of several runs of `skimage.measure.marching_cubes(volume, 0.0)`
(the volume is sampled once, outside the timing, like bench (a) of benches/marching.rs),
and the time to sample the volume with numpy, for reference.
"""
import statistics
import time

import numpy as np
from skimage import measure

N = 256  # cells per axis
R, r = 0.6, 0.25


def sample():
    t = np.linspace(-1.0, 1.0, N + 1)
    # Index order (z, y, x) so that x is fastest, as in certmesh's grid.
    z, y, x = np.meshgrid(t, t, t, indexing="ij")
    s = x * x + y * y + z * z + R * R - r * r
    return s * s - 4 * R * R * (x * x + y * y)


def once():
    """One sampling and one marching cubes call, timed in-process, as JSON."""
    import json

    t0 = time.perf_counter()
    vol = sample()
    t1 = time.perf_counter()
    verts, faces, _, _ = measure.marching_cubes(vol, 0.0, method="lewiner")
    t2 = time.perf_counter()
    print(json.dumps({"sample_s": t1 - t0, "mc_s": t2 - t1, "vertices": len(verts),
                      "triangles": len(faces),
                      "version": __import__("skimage").__version__}))


def main():
    t0 = time.perf_counter()
    vol = sample()
    t_sample = time.perf_counter() - t0
    runs = []
    for _ in range(7):
        t0 = time.perf_counter()
        verts, faces, _, _ = measure.marching_cubes(vol, 0.0, method="lewiner")
        runs.append(time.perf_counter() - t0)
    print(f"volume {vol.shape} {vol.dtype}, numpy sampling {t_sample*1e3:.1f} ms")
    print(f"skimage {__import__('skimage').__version__} marching_cubes (lewiner, float64): "
          f"best {min(runs)*1e3:.1f} ms, median {statistics.median(runs)*1e3:.1f} ms; "
          f"{len(verts)} vertices, {len(faces)} triangles")
    vol32 = vol.astype(np.float32)
    runs = []
    for _ in range(7):
        t0 = time.perf_counter()
        measure.marching_cubes(vol32, 0.0, method="lewiner")
        runs.append(time.perf_counter() - t0)
    print(f"  float32 volume: best {min(runs)*1e3:.1f} ms, median {statistics.median(runs)*1e3:.1f} ms")


if __name__ == "__main__":
    import sys

    once() if "--once" in sys.argv else main()
