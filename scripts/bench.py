#!/usr/bin/env python3
"""Write papers/BENCH.md: each workload of issue 20 timed against its anchor, the two
interleaved in one run (anchor, certmesh, anchor, certmesh, ...), medians of
BENCH_REPS repetitions (default 5), with the machine, the load average before and
after each workload, and the date. Run it through scripts/bench.sh (which builds the
release binary first).

Anchors: scikit-image's measure.marching_cubes (pip install scikit-image numpy) on the
same 256^3 torus volume (benches/skimage_mc.py --once, timed in-process: numpy
sampling + the marching cubes call); the paper's Python GradNormal (quoted, not
measured: 1,141 s); CGAL Mesh_3 (benches/cgal/mesh3_sphere.cpp, built by bench.sh when
libcgal-dev is installed; its path in CGAL_MESH3) on the unit sphere at the size that
gives about as many tetrahedra as the stuffing run. Then each lattice mesher and its
report on 1 and 2 threads (RAYON_NUM_THREADS), interleaved.
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
MESH3 = os.environ.get("CGAL_MESH3")  # benches/cgal/mesh3_sphere.cpp, built by bench.sh
CGAL_VERSION = os.environ.get("CGAL_VERSION", "")
# GradNormal's 52,931,340-tetrahedron genus-2 run: e = 3 * scale_for_count(1, n, sqrt(2)/4)
# (benches/gradnormal.rs), H = sqrt(3)/2.
N_TETS = 52_931_340.0
GN_SCALE = 3.0 * (1.0 / (N_TETS * 0.5 * 0.8660254037844386 * (2 ** 0.5 / 4.0))) ** (1.0 / 3.0)


def load():
    with open("/proc/loadavg") as f:
        return " ".join(f.read().split()[:3])


def run(cmd, env=None):
    """Wall time of a whole process and its stdout (an error stops the script)."""
    full = dict(os.environ, **(env or {}))
    t0 = time.perf_counter()
    p = subprocess.run(cmd, check=True, capture_output=True, text=True, timeout=600, env=full)
    return time.perf_counter() - t0, p.stdout


def certmesh(args, env=None):
    """Whole-process wall time and the report's mesher time (`seconds`)."""
    wall, out = run([CERTMESH] + args + ["--json"], env)
    rep = json.loads(out)
    return wall, rep["seconds"], rep


def skimage():
    wall, out = run([sys.executable, os.path.join(ROOT, "benches", "skimage_mc.py"), "--once"])
    r = json.loads(out)
    return r["sample_s"] + r["mc_s"], r


def med(xs):
    return statistics.median(xs) if xs else float("nan")


def ms(x):
    if x != x:
        return "—"
    return f"{x * 1e3:,.1f} ms" if x < 0.01 else f"{x * 1e3:,.0f} ms"


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
    # 4: stuffing on the sphere (whole process), against CGAL Mesh_3 on the same sphere
    # at about the same number of tetrahedra (resolution 42: 142,704; CGAL cell size 0.05:
    # about 143,500), interleaved.
    l0 = load()
    st = ["mesh", "sphere", "--algo", "stuffing", "--resolution", "42",
          "-o", os.path.join(TMP, "bench-sphere.vtk")]
    s_wall, s_mesher, c_time = [], [], []
    tets, crep, srep = None, None, None
    # Stuffing's checks (issue 20: at most 30 % of the run), per workload and thread
    # count: lists of (checks, boundary, mesher, whole process) seconds.
    shares = {}

    def share(name, threads, wall, rep):
        st = rep.get("stats") or {}
        shares.setdefault((name, threads), []).append(
            (st.get("seconds_checks", float("nan")), st.get("seconds_boundary", float("nan")),
             rep["seconds"], wall))
    for _ in range(REPS):
        if MESH3:
            _, out = run([MESH3, "0.05", "0.05", "0.005"])
            crep = json.loads(out)
            c_time.append(crep["seconds"])
        w, s, srep = certmesh(st)
        share("sphere, resolution 42", f"{os.cpu_count()} (default)", w, srep)
        s_wall.append(w)
        s_mesher.append(s)
        tets = srep.get("tetrahedra")
    l1 = load()
    st_stats = srep.get("stats") or {}
    ours = (f"{tets:,} tetrahedra, {tets / med(s_mesher):,.0f}/s, dihedral "
            f"{st_stats.get('min_dihedral_deg', float('nan')):.1f}°–{st_stats.get('max_dihedral_deg', float('nan')):.1f}°")
    if crep:
        cgal = (f"CGAL {CGAL_VERSION} Mesh_3, measured: facet angle 25, facet size 0.05, facet distance "
                f"0.005, radius-edge 2, cell size 0.05, its default perturb and exude; "
                f"{crep['tetrahedra']:,} tetrahedra, {crep['tetrahedra'] / med(c_time):,.0f}/s, dihedral "
                f"{crep['min_dihedral_deg']:.1f}°–{crep['max_dihedral_deg']:.1f}°")
        a = med(c_time)
    else:
        cgal = "CGAL Mesh_3: not measured (libcgal-dev not installed; quoted from issue 20: 143,898 tetrahedra in 2.50 s)"
        a = 2.50
    rows.append((f"stuffing, sphere ({ours}), mesher time", a, med(s_mesher), cgal, f"{l0} → {l1}"))
    rows.append((f"stuffing, sphere ({tets:,} tetrahedra), whole process", a, med(s_wall), cgal, f"{l0} → {l1}"))

    # 5: 1 and 2 threads, interleaved: mesher time (the report's `seconds`), the
    # report's measures (its `metrics_seconds`, computed while the mesh is written) and
    # the rest of the process (report, writing, start-up), for the workloads and
    # for each lattice mesher at its default settings.
    thread_rows = []
    for name, args in [
        ("mc, torus 256³", torus),
        ("mt, torus 128³", ["mesh", "torus", "--algo", "mt", "--resolution", "128",
                           "-o", os.path.join(TMP, "bench-torus-mt.ply")]),
        ("gradnormal, genus 2, 52.9 M tetrahedra", gn),
        ("stuffing, sphere, resolution 42", st),
        ("mc, torus, defaults", ["mesh", "torus", "--algo", "mc",
                                 "-o", os.path.join(TMP, "bench-torus-d.ply")]),
        ("gradnormal, genus 2, defaults", ["mesh", "genus2", "--algo", "gradnormal",
                                          "-o", os.path.join(TMP, "bench-genus2-d.ply")]),
        ("stuffing, sphere, defaults", ["mesh", "sphere", "--algo", "stuffing",
                                       "-o", os.path.join(TMP, "bench-sphere-d.vtk")]),
    ]:
        l0 = load()
        t = {1: ([], [], []), 2: ([], [], [])}
        for _ in range(REPS):
            for n in (1, 2):
                w, s, rep = certmesh(args, {"RAYON_NUM_THREADS": str(n)})
                if name.startswith("stuffing"):
                    share(name.removeprefix("stuffing, "), str(n), w, rep)
                t[n][0].append(s)
                t[n][1].append(rep["metrics_seconds"])
                t[n][2].append(w - s)
        l1 = load()
        thread_rows.append((name, [med(t[n][k]) for k in range(3) for n in (1, 2)], f"{l0} → {l1}"))

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
        "Each lattice mesher on 1 and 2 threads (`RAYON_NUM_THREADS`), interleaved, medians; "
        "\"rest\" is the whole process minus the mesher time (report, writing, start-up). Serial by "
        "design in the report: the union-find of components and boundary loops, the count and "
        "fill passes of the vertex buckets (a counting sort), the counting sort of the few "
        "thousand surface points into the sweeps' grid (the sweeps over the triangles are "
        "parallel), and writing the file (on its own thread beside the measures); "
        "in stuffing, the fill passes of the face buckets.",
        "",
        "\"Metrics\" is the report's own time (`metrics_seconds` of the JSON: topology, angles, "
        "Hausdorff estimate at the default `--metrics fast`), measured in the process while the "
        "mesh file is written beside it; its share of the mesher's time is the issue's target "
        "(at most 25 %).",
        "",
        "| workload | load average | mesher, 1 thread | 2 threads | speed-up | metrics, 1 thread | 2 threads | speed-up | metrics / mesher, 1 thread | 2 threads | rest, 1 thread | 2 threads |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, (m1, m2, x1, x2, r1, r2), la in thread_rows:
        lines.append(f"| {name} | {la} | {ms(m1)} | {ms(m2)} | {m1 / m2:.2f} | {ms(x1)} | {ms(x2)} | "
                     f"{x1 / x2:.2f} | {100 * x1 / m1:.0f} % | {100 * x2 / m2:.0f} % | {ms(r1)} | {ms(r2)} |")
    lines += [
        "",
        "Stuffing's checks (issue 20: the exact conformity and orientation checks and the quality "
        "summary, at most 30 % of the run), from the mesher's own timers (`seconds_checks`, "
        "`seconds_boundary` in the JSON's stats), medians over the runs above. \"Boundary\" is "
        "the grouping of the tetrahedra's faces and the boundary surface taken from it: part of "
        "the output, and the faces the conformity check reads.",
        "",
        "| workload | threads | checks | boundary | mesher | whole process | checks / mesher | checks / whole process | checks + boundary / mesher |",
        "|---|---:|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for (name, n), xs in shares.items():
        c, b, m, w = (med([x[k] for x in xs]) for k in range(4))
        lines.append(f"| {name} | {n} | {ms(c)} | {ms(b)} | {ms(m)} | {ms(w)} | {100 * c / m:.0f} % | "
                     f"{100 * c / w:.0f} % | {100 * (c + b) / m:.0f} % |")
    lines += [
        "",
        "Criterion benches per workload: `cargo bench --bench end_to_end` (evaluation + mesh + "
        "report + writing to a memory buffer), `--bench evaluator` (batch evaluation), "
        "`--bench marching`, `--bench gradnormal`, `--bench stuffing` (with `stuffing_checks`: the "
        "face grouping, the boundary, the summary and the conformity check, each on its own), "
        "`--bench bvh`, and "
        "`--bench report` (the report part by part, on 1 and 2 threads: the 256³ MC torus, and the "
        "MC torus, the marching-tetrahedra torus and GradNormal genus 2 at their defaults, each "
        "with floors: of a report that looks at every triangle once (one gradient, or one Newton "
        "projection, per triangle), of the topology (star lists and edge count) and of the angle "
        "range (signed squared cosines), and the surface → mesh distances by the sweeps and by "
        "the centroid grid).",
        "",
        "Where the report's time goes, part by part, measured by hand and dated: "
        "`papers/bench-report.md` (not rewritten by this script).",
        "",
    ]
    with open(OUT, "w") as f:
        f.write("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
