"""certmesh from Python against scikit-image's marching cubes, in one process.

    pip install scikit-image && python python/benchmarks/bench_mc.py [--resolution 256] [--repeat 7]

Workload: the catalog torus, (x² + y² + z² + R² − r²)² − 4R²(x² + y²) with R = 0.6,
r = 0.25, on its domain [-1, 1]³, at N³ cells.
* certmesh: `certmesh.mesh(formula=..., algo="mc", resolution=N, report=False)` (and
  with `prune=True`, which skips cells an interval enclosure proves empty),
  sampling included, arrays in hand; and the mesher's own time (`r.seconds`), whose
  difference to the call is the binding's overhead.
* scikit-image: the volume sampled with numpy (meshgrid, the same formula), then
  `skimage.measure.marching_cubes(volume, 0)`; and the MC call alone.
Prints medians over --repeat runs, interleaved, with the load average.
"""
import argparse
import json
import os
import statistics
import time

import numpy as np

import certmesh


def torus_numpy(entry, n):
    d = entry["domain"]
    lo, hi = np.array(d["min"]), np.array(d["max"])
    axes = [np.linspace(lo[k], hi[k], n + 1) for k in range(3)]
    x, y, z = np.meshgrid(*axes, indexing="ij")
    return eval_formula(entry["formula"], x, y, z), (hi - lo) / n


def eval_formula(text, x, y, z):
    return eval(text.replace("^", "**"), {"x": x, "y": y, "z": z, "sqrt": np.sqrt, "abs": np.abs})


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--resolution", type=int, default=256)
    ap.add_argument("--repeat", type=int, default=7)
    ap.add_argument("--json", action="store_true")
    a = ap.parse_args()
    from skimage import measure

    entry = next(e for e in certmesh.surfaces() if e["name"] == "torus")
    n = a.resolution
    times = {"certmesh call": [], "certmesh mesher": [], "certmesh call, prune": [],
             "skimage total": [], "skimage mc": []}
    dom = [*entry["domain"]["min"], *entry["domain"]["max"]]
    tris = {}
    for _ in range(a.repeat):
        t = time.perf_counter()
        r = certmesh.mesh(formula=entry["formula"], domain=dom, algo="mc", resolution=n,
                          report=False, progress=False)
        times["certmesh call"].append(time.perf_counter() - t)
        times["certmesh mesher"].append(r.seconds)
        tris["certmesh"] = len(r.faces)
        # prune=True skips the cells an interval enclosure proves empty (same mesh)
        t = time.perf_counter()
        r2 = certmesh.mesh(formula=entry["formula"], domain=dom, algo="mc", resolution=n,
                           report=False, progress=False, prune=True)
        times["certmesh call, prune"].append(time.perf_counter() - t)
        assert len(r2.faces) == len(r.faces)
        t = time.perf_counter()
        vol, spacing = torus_numpy(entry, n)
        t1 = time.perf_counter()
        v, f, _, _ = measure.marching_cubes(vol, 0.0, spacing=tuple(spacing))
        t2 = time.perf_counter()
        times["skimage total"].append(t2 - t)
        times["skimage mc"].append(t2 - t1)
        tris["skimage"] = len(f)
    med = {k: statistics.median(v) for k, v in times.items()}
    out = {
        "resolution": n,
        "repeat": a.repeat,
        "load_average": os.getloadavg(),
        "median_seconds": med,
        "triangles": tris,
        "speedup_end_to_end": med["skimage total"] / med["certmesh call"],
        "speedup_vs_mc_call_alone": med["skimage mc"] / med["certmesh call"],
        "speedup_end_to_end_prune": med["skimage total"] / med["certmesh call, prune"],
        "binding_overhead": (med["certmesh call"] - med["certmesh mesher"]) / med["certmesh mesher"],
    }
    if a.json:
        print(json.dumps(out, indent=1))
    else:
        for k, v in med.items():
            print(f"{k:22} {v * 1e3:9.1f} ms")
        print(f"triangles          certmesh {tris['certmesh']}, scikit-image {tris['skimage']}")
        print(f"end-to-end speed-up over scikit-image: {out['speedup_end_to_end']:.2f}x "
              f"(over its MC call alone: {out['speedup_vs_mc_call_alone']:.2f}x)")
        print(f"with prune=True: {out['speedup_end_to_end_prune']:.2f}x end to end")
        print(f"binding overhead (call - mesher) / mesher: {100 * out['binding_overhead']:.1f}%")
        print(f"load average {out['load_average']}")


if __name__ == "__main__":
    main()
