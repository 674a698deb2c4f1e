#!/usr/bin/env python3
"""Assemble papers/stuffing/PROOF.md's tables from `proofs stuffing --row R --json`
summaries (one file per row, DIR/R.summary.json) and the certificates (DIR/R.json, for
the slowest cases). Usage: proof_md.py DIR > table.md"""
import json, sys, os
from collections import Counter

ROWS = ["max-dihedral-unsafe", "min-dihedral-unsafe", "max-dihedral-safe", "min-dihedral-safe",
        "min-dihedral-safe-ordered", "max-dihedral-double", "min-dihedral-double",
        "min-dihedral-double-ordered", "max-exposed-safe", "max-exposed-safe-ordered",
        "min-exposed-unsafe", "min-exposed-safe", "min-exposed-safe-ordered"]
d = sys.argv[1]
out = []
def fmt(x): return "%.6f" % x
out.append("| row | bound | paper | certified extreme (°) | verdict | within 0.0001° of the paper |")
out.append("|---|---|---|---|---|---|")
stats = []
wit = []
for r in ROWS:
    p = os.path.join(d, r + ".summary.json")
    if not os.path.exists(p) or os.path.getsize(p) == 0:
        out.append("| %s | (not run) | | | | |" % r)
        continue
    s = json.load(open(p))
    for b in s["bounds"]:
        if b["paper"] is None:
            out.append("| %s | %s | n/a | not certified (tetrahedra can be flat) | - | - |" % (r, b["bound"]))
            continue
        lo, hi = b["certified_deg"]
        out.append("| %s | %s | %.4f | [%s, %s] | %s | %s |" % (r, b["bound"], b["paper"], fmt(lo), fmt(hi), b["verdict"], b["tight"]))
        w = b["witness"]
        if w:
            verts = "; ".join("(%.5f, %.5f, %.5f)" % tuple(v) for v in w["vertices_h"])
            kinds = " ".join("%s" % c["kind"][0] for c in w["case"])
            wit.append("| %s | %s | %s | %s |" % (r, b["bound"], kinds, verts))
    sf = s["safe"]
    stats.append((r, s["cases"]["raw"], s["cases"]["distinct"], s["unreduced_cases"], s["problems"], s["leaves"], s["unresolved"], s["seconds"], sf))
print("\n".join(out))
print()
print("### Run statistics and the safe property\n")
print("| row | output-tet cases raw -> distinct | unreduced | problems | leaves | unresolved | seconds | safe: BCC cases raw -> distinct | min volume / unwarped | safe verdict |")
print("|---|---|---|---|---|---|---|---|---|---|")
for (r, raw, dist, unr, pr, lv, un, sec, sf) in stats:
    print("| %s | %d -> %d | %d | %d | %d | %d | %.0f | %d -> %d | %.5f | %s%s |" % (r, raw, dist, unr, pr, lv, un, sec, sf["counts"]["raw"], sf["counts"]["distinct"], sf["min_ratio"], sf["verdict"], (" (" + sf["note"] + ")") if sf["note"] else ""))
print()
print("### Witness configurations\n")
print("Vertex kinds: F fixed lattice point, C cut point, W warped lattice point. Coordinates in units of the black edge length h (lattice points at integer and half-integer coordinates).\n")
print("| row | bound | kinds | vertices |")
print("|---|---|---|---|")
print("\n".join(wit))
# Slowest cases: most leaves, from the certificates.
print()
print("### Slowest cases (most leaves)\n")
print("| row | case | leaves |")
print("|---|---|---|")
for r in ROWS:
    p = os.path.join(d, r + ".json")
    sp = os.path.join(d, r + ".summary.json")
    if not os.path.exists(p) or not os.path.exists(sp) or os.path.getsize(sp) == 0:
        continue
    c = json.load(open(p))
    cnt = Counter()
    for pc in c["problems"]:
        cnt[pc["case"]] += len(pc["leaves"])
    for case, n in cnt.most_common(2):
        print("| %s | %d | %d |" % (r, case, n))
