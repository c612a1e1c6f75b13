#!/usr/bin/env python3
"""Classifies the exact contacts of a closed triangle mesh (OBJ), independently of the C++ code.

Usage: scripts/contact_classes.py MESH.obj

Finds every pair of triangles without a shared vertex that meet non-generically (exact rational
arithmetic on the file's doubles, Python's fractions): edge-through-edge crossings, vertices on
triangles, coplanar pairs. For each edge-through-edge crossing X of edges e and f it says whether
each edge crosses the other sheet at X ("cross": the two halves of f lie on opposite sides of the
hinge of e's two triangles) or touches it ("touch-out"/"touch-in": both halves outside/inside;
"on": a half lies on the other sheet, as in coplanar contacts).
A crossing where both edges cross is resolved the same way by every perturbation (the
intersection curve passes by X on one side or the other); a touching one is a tangency, where
the perturbation decides how the curves and regions meeting at X connect. Used for the
doubleLoopWithCube analysis in BENCHMARKS.md (issue 16). Slow (pure Python), fine for ~10k
triangles.
"""
import math
import sys
from fractions import Fraction as Fr
from collections import defaultdict, Counter
path=sys.argv[1]
V=[];F=[]
for l in open(path):
    s=l.split()
    if not s: continue
    if s[0]=='v': V.append(tuple(float(x) for x in s[1:4]))
    if s[0]=='f':
        idx=[int(x.split('/')[0])-1 for x in s[1:]]
        for k in range(1,len(idx)-1): F.append((idx[0],idx[k],idx[k+1]))
VX=[tuple(Fr(c) for c in p) for p in V]
def sub(a,b): return (a[0]-b[0],a[1]-b[1],a[2]-b[2])
def det3(u,v,w): return u[0]*(v[1]*w[2]-v[2]*w[1])-u[1]*(v[0]*w[2]-v[2]*w[0])+u[2]*(v[0]*w[1]-v[1]*w[0])
def orient(a,b,c,d):
    # sign of det(b-a,c-a,d-a): exact (rationals from the file's doubles)
    xa,xb,xc,xd=VX[a],VX[b],VX[c],VX[d]
    x=det3(sub(xb,xa),sub(xc,xa),sub(xd,xa))
    return (x>0)-(x<0)
# candidate pairs: grid
lo=[min(p[k] for p in V) for k in range(3)]; hi=[max(p[k] for p in V) for k in range(3)]
cell=0.05
grid=defaultdict(list)
def bb(t): 
    ps=[V[i] for i in F[t]]
    return [min(p[k] for p in ps) for k in range(3)],[max(p[k] for p in ps) for k in range(3)]
BB=[bb(t) for t in range(len(F))]
for t in range(len(F)):
    a,b=BB[t]
    for i in range(int((a[0]-lo[0])/cell),int((b[0]-lo[0])/cell)+1):
        for j in range(int((a[1]-lo[1])/cell),int((b[1]-lo[1])/cell)+1):
            for k in range(int((a[2]-lo[2])/cell),int((b[2]-lo[2])/cell)+1):
                grid[(i,j,k)].append(t)
pairs=set()
for ts in grid.values():
    for x in range(len(ts)):
        for y in range(x+1,len(ts)):
            s,t=ts[x],ts[y]
            if s>t: s,t=t,s
            if (s,t) in pairs: continue
            A,B=BB[s],BB[t]
            if all(A[0][k]<=B[1][k] and B[0][k]<=A[1][k] for k in range(3)):
                if not set(F[s])&set(F[t]): pairs.add((s,t))
print('candidate pairs',len(pairs),file=sys.stderr)
def orientX(a,b,c,p):  # exact, p a Fraction point, a,b,c vertex ids
    xa,xb,xc=VX[a],VX[b],VX[c]
    x=det3(sub(xb,xa),sub(xc,xa),sub(p,xa)); return (x>0)-(x<0)
def drop_axis(a,b,c):
    n=[abs(x) for x in det_normal(a,b,c)]
    return n.index(max(n))
def det_normal(a,b,c):
    u=sub(VX[b],VX[a]);v=sub(VX[c],VX[a])
    return (u[1]*v[2]-u[2]*v[1],u[2]*v[0]-u[0]*v[2],u[0]*v[1]-u[1]*v[0])
def o2(p,q,r,ax):
    i,j=[k for k in range(3) if k!=ax]
    x=(q[i]-p[i])*(r[j]-p[j])-(q[j]-p[j])*(r[i]-p[i]); return (x>0)-(x<0)
def seg_seg_point(p,q,r,s):
    # p,q,r,s coplanar Fraction points; returns intersection point if the segments cross at one
    # point (including endpoints), 'overlap' if collinear overlapping, None otherwise
    n=(lambda u,v:(u[1]*v[2]-u[2]*v[1],u[2]*v[0]-u[0]*v[2],u[0]*v[1]-u[1]*v[0]))(sub(q,p),sub(s,r))
    if n==(0,0,0):
        return None  # parallel (collinear ignored here; counted separately if ever)
    ax=max(range(3),key=lambda k:abs(n[k]))
    d1=o2(p,q,r,ax);d2=o2(p,q,s,ax);d3=o2(r,s,p,ax);d4=o2(r,s,q,ax)
    if d1*d2>0 or d3*d4>0: return None
    # solve p+t(q-p) on line r s
    i,j=[k for k in range(3) if k!=ax]
    den=(q[i]-p[i])*(s[j]-r[j])-(q[j]-p[j])*(s[i]-r[i])
    t=((r[i]-p[i])*(s[j]-r[j])-(r[j]-p[j])*(s[i]-r[i]))/den
    return tuple(p[k]+t*(q[k]-p[k]) for k in range(3))
edge_faces=defaultdict(list)
for t,(a,b,c) in enumerate(F):
    for u,v,w in ((a,b,c),(b,c,a),(c,a,b)): edge_faces[frozenset((u,v))].append((t,w))
contacts={}  # key -> (kind, point)
kinds=Counter()
pair_kinds=Counter()
for (a,b) in sorted(pairs):
    ta,tb=F[a],F[b]
    oa=[orient(tb[0],tb[1],tb[2],v) for v in ta]; ob=[orient(ta[0],ta[1],ta[2],v) for v in tb]
    if len(set(oa))==1 and oa[0]!=0: continue
    if len(set(ob))==1 and ob[0]!=0: continue
    if 0 not in oa and 0 not in ob: 
        # may still have edge-edge contact: edges coplanar crossing at an interior point
        pass
    found=False
    if oa==[0,0,0]:
        contacts[('coplanar',a,b)]=('coplanar',None); pair_kinds['coplanar']+=1; continue
    for i in range(3):
        for j in range(3):
            e=(ta[i],ta[(i+1)%3]); f=(tb[j],tb[(j+1)%3])
            if orient(e[0],e[1],f[0],f[1])!=0: continue
            X=seg_seg_point(VX[e[0]],VX[e[1]],VX[f[0]],VX[f[1]])
            if X is None: continue
            key=('edge-edge',frozenset(e),frozenset(f)) if min(e)<min(f) else ('edge-edge',frozenset(f),frozenset(e))
            contacts[key]=(key[0],X,frozenset(e),frozenset(f)); found=True
    # vertex on the other's interior
    for side,(t1,t2,o) in enumerate(((ta,tb,oa),(tb,ta,ob))):
        for k in range(3):
            if o[k]!=0: continue
            p=VX[t1[k]]; ax=max(range(3),key=lambda m:abs(det_normal(*t2)[m]))
            s=[o2(VX[t2[0]],VX[t2[1]],p,ax),o2(VX[t2[1]],VX[t2[2]],p,ax),o2(VX[t2[2]],VX[t2[0]],p,ax)]
            if (min(s)>=0 or max(s)<=0):
                contacts[('vertex-face',t1[k],b if side==0 else a)]=('vertex-face',p); found=True
    pair_kinds['found' if found else ('zero-no-contact' if (0 in oa or 0 in ob) else 'generic')]+=1
def sub(a,b): return (a[0]-b[0],a[1]-b[1],a[2]-b[2])
def det3(u,v,w): return u[0]*(v[1]*w[2]-v[2]*w[1])-u[1]*(v[0]*w[2]-v[2]*w[0])+u[2]*(v[0]*w[1]-v[1]*w[0])
def sgn(x): return (x>0)-(x<0)
edge_faces=defaultdict(list)
for t,(a,b,c) in enumerate(F):
    for u,v,w in ((a,b,c),(b,c,a),(c,a,b)): edge_faces[(u,v)].append((t,w))
def hinge(e):
    u,v=tuple(e)
    (t1,w1),=edge_faces[(u,v)]; (t2,w2),=edge_faces[(v,u)]
    return (u,v,w1),(v,u,w2)
def above(f,p): return sgn(det3(sub(VX[f[1]],VX[f[0]]),sub(VX[f[2]],VX[f[0]]),sub(p,VX[f[0]])))
def side(e,p):
    f1,f2=hinge(e)
    convex = above(f1,VX[f2[2]])<0
    d1,d2=above(f1,p),above(f2,p)
    if d1==0 or d2==0: return 0
    out = (d1>0 or d2>0) if convex else (d1>0 and d2>0)
    return 1 if out else -1
t=Fr(1,10**6)
cls=Counter(); rows=[]
print('contacts by kind:', dict(Counter(v[0] for v in contacts.values())))
for key,val in contacts.items():
    if val[0]!='edge-edge': continue
    kind,X,ea,eb=val
    res=[]
    for e,f in ((ea,eb),(eb,ea)):
        # points of f just before and after X, side w.r.t. hinge e
        p,q=tuple(f)
        s=[side(e,tuple(X[k]+t*(VX[w][k]-X[k]) for k in range(3))) for w in (p,q)]
        res.append('on' if 0 in s else 'cross' if s[0]*s[1]<0 else ('touch-out' if s[0]>0 else 'touch-in'))
    c=tuple(sorted(res)); cls[c]+=1
    Xf=[float(x) for x in X]
    rows.append((Xf,sorted(ea),sorted(eb),c))
print('edge-through-edge classes:', dict(cls))
for r in sorted(rows, key=lambda r: r[3]): print(' '.join('%.6f'%x for x in r[0]), 'edge', r[1], 'edge', r[2], *r[3])
