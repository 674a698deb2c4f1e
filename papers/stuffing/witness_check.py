#!/usr/bin/env python3
"""Independent float recomputation of the witness configurations of `proofs stuffing --json`
summaries (certs/ROW.summary.json): usage witness_check.py ROW..."""
import json, math, itertools, sys
def sub(a,b): return [a[i]-b[i] for i in range(3)]
def dot(a,b): return sum(a[i]*b[i] for i in range(3))
def cross(a,b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def ang(u,v): return math.degrees(math.acos(max(-1,min(1,dot(u,v)/math.sqrt(dot(u,u)*dot(v,v))))))
def dihedrals(p):
    out=[]
    for i,j in itertools.combinations(range(4),2):
        k,l=[m for m in range(4) if m not in (i,j)]
        u=sub(p[j],p[i]); out.append(ang(cross(u,sub(p[k],p[i])), cross(u,sub(p[l],p[i]))))
    return out
def planes(p, faces):
    out=[]
    for f in faces:
        for a in range(3):
            x,y,z=p[f[a]],p[f[(a+1)%3]],p[f[(a+2)%3]]
            out.append(ang(sub(y,x),sub(z,x)))
    return out
for r in sys.argv[1:]:
    d=json.load(open((sys.argv[1] if False else 'certs/%s.summary.json' % r)))
    for b in d['bounds']:
        w=b['witness']
        if not w: continue
        p=w['vertices_h']
        if 'dihedral' in b['bound']:
            v=dihedrals(p)
        else:
            faces=[f for f in [[1,2,3],[0,3,2],[0,1,3],[0,2,1]] if b['bound'].endswith('plane') or all(w['case'][k]['kind']!='Fixed' for k in f)]
            v=planes(p,faces)
        x=min(v) if b['bound'].startswith('min') else max(v)
        print(r, b['bound'], 'paper', b['paper'], 'float recomputation %.6f'%x, 'certified', ['%.6f'%t for t in b['certified_deg']])
