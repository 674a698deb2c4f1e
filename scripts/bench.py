#!/usr/bin/env python3
"""Write papers/BENCH.md: each workload of issue 20 timed against its anchor, the two
interleaved in one run (anchor, certmesh, anchor, certmesh, ...), medians of
BENCH_REPS repetitions (default 5), with the machine, the load average before and
after each workload, and the date. Run it through scripts/bench.sh (which builds the
release binary first).

Anchors: scikit-image's measure.marching_cubes (pip install scikit-image numpy) on the
same 256^3 torus volume (benches/skimage_mc.py --once, timed in-process: numpy
sampling + the marching cubes call); the paper's Python GradNormal (quoted, not
measured: 1,141 s); CGAL Mesh_3 is not measured here (left for later; see the note
in the output).
"""
import json
import os
import platform
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CERTMESH = os.environ.get("CERTMESH", os.path.join(ROOT, "target", "release", "certmesh"))
REPS = int(os.environ.get("BENCH_REPS", "5"))
OUT = os.path.join(ROOT, "papers", "BENCH.md")
TMP = os.environ.get("TMPDIR", "/tmp")
# GradNormal's 52,931,340-tetrahedron genus-2 run: e = 3 * scale_for_count(1, n, sqrt(2)/4)
# (benches/gradnormal.rs), H = sqrt(3)/2.
N_TETS = 52_931_340.0
GN_SCALE = 3.0 * (1.0 / (N_TETS * 0.5 * 0.8660254037844386 * (2 ** 0.5 / 4.0))) ** (1.0 / 3.0)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def run(cmd):
    """Wall time of a whole process and its stdout (an error stops the script)."""
    t0 = time.perf_counter()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=600)
    return time.perf_counter() - t0, p.stdout


def certmesh(args):
    """Whole-process wall time and the report's mesher time (`seconds`)."""
    wall, out = run([CERTMESH] + args + ["--json"])
    rep = json.loads(out)
    return wall, rep["seconds"], rep


def skimage():
    wall, out = run([sys.executable, os.path.join(ROOT, "benches", "skimage_mc.py"), "--once"])
    r = json.loads(out)
    return r["sample_s"] + r["mc_s"], r


def med(xs):
    return statistics.median(xs) if xs else float("nan")


def ms(x):
    return "—" if x != x else f"{x * 1e3:,.0f} ms"


def main():
    rows = []
    torus = ["mesh", "torus", "--algo", "mc", "--resolution", "256", "--prune",
             "-o", os.path.join(TMP, "bench-torus.ply")]
    # 1-2: marching cubes on the 256^3 torus, against scikit-image in the same loop.
    l0 = load()
    anchor, mesher, wall_none, wall_fast, wall_full = [], [], [], [], []
    sk = None
    for _ in range(REPS):
        a, sk = skimage()
        anchor.append(a)
        w, s, rep = certmesh(torus + ["--metrics", "none"])
        mesher.append(s)
        wall_none.append(w)
        w, _, _ = certmesh(torus)
        wall_fast.append(w)
        w, _, _ = certmesh(torus + ["--metrics", "full"])
        wall_full.append(w)
    l1 = load()
    note = f"scikit-image {sk['version']}: numpy sampling + marching_cubes (lewiner), in-process"
    rows.append(("MC 256³ torus, evaluation included (mesher time)", med(anchor), med(mesher),
                 note, f"{l0} → {l1}"))
    for name, w in [("none", wall_none), ("fast (default)", wall_fast), ("full", wall_full)]:
        rows.append((f"`certmesh mesh torus --algo mc --resolution 256 --prune -o t.ply --metrics {name.split()[0]}`, whole process",
                     med(anchor), med(w), "the same anchor (its MC call and sampling only)", f"{l0} → {l1}"))
    # 3: GradNormal, 52.9 M tetrahedra on genus 2 (whole process).
    l0 = load()
    gn = ["mesh", "genus2", "--algo", "gradnormal", "--scale", repr(GN_SCALE),
          "-o", os.path.join(TMP, "bench-genus2.ply")]
    g_wall, g_mesher, g_none = [], [], []
    for _ in range(REPS):
        w, s, _ = certmesh(gn)
        g_wall.append(w)
        g_mesher.append(s)
        w, _, _ = certmesh(gn + ["--metrics", "none"])
        g_none.append(w)
    l1 = load()
    quoted = "the paper's Python, quoted (1,141 s), not measured"
    rows.append(("GradNormal genus 2, 52.9 M tetrahedra (mesher time)", 1141.0, med(g_mesher), quoted, f"{l0} → {l1}"))
    rows.append(("GradNormal genus 2, 52.9 M tetrahedra, whole process (default report)", 1141.0, med(g_wall), quoted, f"{l0} → {l1}"))
    rows.append(("GradNormal genus 2, 52.9 M tetrahedra, whole process (--metrics none)", 1141.0, med(g_none), quoted, f"{l0} → {l1}"))
    # 4: stuffing on the sphere (whole process); CGAL Mesh_3 not measured here.
    l0 = load()
    st = ["mesh", "sphere", "--algo", "stuffing", "-o", os.path.join(TMP, "bench-sphere.vtk")]
    s_wall, s_mesher = [], []
    tets = None
    for _ in range(REPS):
        w, s, rep = certmesh(st)
        s_wall.append(w)
        s_mesher.append(s)
        tets = rep.get("tetrahedra")
    l1 = load()
    cgal = "CGAL Mesh_3: not measured (quoted from issue 20: 143,898 tetrahedra in 2.50 s)"
    rows.append((f"stuffing, sphere ({tets:,} tetrahedra), mesher time", 2.50, med(s_mesher), cgal, f"{l0} → {l1}"))
    rows.append((f"stuffing, sphere ({tets:,} tetrahedra), whole process", 2.50, med(s_wall), cgal, f"{l0} → {l1}"))

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(l.split(":", 1)[1].strip() for l in f if l.startswith("model name"))
    except (OSError, StopIteration):
        pass
    lines = [
        "# Benchmarks: certmesh against its anchors",
        "",
        f"Generated by `scripts/bench.sh` on {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}. "
        f"Machine: {cpu}, {os.cpu_count()} logical CPUs (shared: see the load averages), "
        f"{platform.system()} {platform.release()}. Medians of {REPS} interleaved repetitions. "
        "Ratio = anchor time / certmesh time (above 1: certmesh is faster). Timings on a "
        "machine shared with other engineers' builds: compare within a row, not across runs.",
        "",
        "| workload | anchor | anchor time | certmesh time | ratio | load average (before → after) |",
        "|---|---|---:|---:|---:|---|",
    ]
    for name, a, c, note, la in rows:
        a_s = f"{a:,.2f} s" if a >= 10 else ms(a)
        # A quoted anchor ran elsewhere (another machine, another mesh size): no ratio.
        if "quoted" in note:
            r_s = "— (quoted)"
        else:
            r_s = f"{a / c:,.1f}" if c == c and c > 0 and a == a else "—"
        lines.append(f"| {name} | {note} | {a_s} | {ms(c)} | {r_s} | {la} |")
    lines += [
        "",
        "Criterion benches per workload: `cargo bench --bench end_to_end` (evaluation + mesh + "
        "report + writing to a memory buffer), `--bench evaluator` (batch evaluation), "
        "`--bench marching`, `--bench gradnormal`, `--bench stuffing`, `--bench bvh`.",
        "",
    ]
    with open(OUT, "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
