#!/usr/bin/env python3
"""Calibrates [LoopClosure] informationScale against a log's ground-truth relations.

The loop-closure graph's consecutive edges carry informationScale^-1 x the PM Hessian of each
keyframe's match. For every relation (t1, t2) of the .relations file, the online trajectory's
relative pose error e is compared with the covariance the graph would predict for it (the
keyframes' H^-1 between t1 and t2, propagated to t2 through the heading); the median of
e' S^-1 e over the median of a chi-square with 3 degrees of freedom (2.366) is the scale at which
the graph's edges are honest.

  PMSLAM_KEYFRAMES_DUMP=/tmp/kf.txt build/bin/pm-slam-app-instrumented --config config/default.ini LOG.clf --out OUT
  bench/calibrate_information.py /tmp/kf.txt OUT/trajectory_online.txt LOG.relations

pm-slam-app-instrumented is pm-slam-app with the test and benchmark hooks (built with the tests and
benchmarks, never installed); pm-slam-app itself reads no PMSLAM_* variable. Pure Python 3 (no numpy).
"""
import sys, math, bisect
def inv3(m):
    a,b,c=m[0];d,e,f=m[1];g,h,i=m[2]
    A=e*i-f*h;B=-(d*i-f*g);C=d*h-e*g
    det=a*A+b*B+c*C
    if abs(det)<1e-300: return None
    D=-(b*i-c*h);E=a*i-c*g;F=-(a*h-b*g);G=b*f-c*e;H=-(a*f-c*d);I=a*e-b*d
    return [[A/det,D/det,G/det],[B/det,E/det,H/det],[C/det,F/det,I/det]]
def mm(a,b): return [[sum(a[i][k]*b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]
def tr(a): return [[a[j][i] for j in range(3)] for i in range(3)]
kf=[]
for l in open(sys.argv[1]):
    v=list(map(float,l.split()))
    H=[[v[4],v[5],v[6]],[v[5],v[7],v[8]],[v[6],v[8],v[9]]]
    kf.append((v[0],v[1],v[2],v[3],inv3(H)))
kt=[k[0] for k in kf]
traj=[]
for l in open(sys.argv[2]):
    if l.startswith('#'): continue
    v=list(map(float,l.split())); traj.append(v)
tt=[t[0] for t in traj]
def at(t):
    i=bisect.bisect_left(tt,t-1e-4)
    if i<len(tt) and abs(tt[i]-t)<1e-3: return traj[i]
    return None
qs=[]
for l in open(sys.argv[3]):
    v=list(map(float,l.split()))
    t1,t2=v[0],v[1]
    if t2<t1: continue
    p1,p2=at(t1),at(t2)
    if p1 is None or p2 is None: continue
    c,s=math.cos(p1[3]),math.sin(p1[3])
    dx,dy=p2[1]-p1[1],p2[2]-p1[2]
    rx,ry=c*dx+s*dy,-s*dx+c*dy; rth=math.remainder(p2[3]-p1[3],2*math.pi)
    e=[rx-v[2],ry-v[3],math.remainder(rth-v[7],2*math.pi)]
    i0=bisect.bisect_right(kt,t1); i1=bisect.bisect_right(kt,t2)
    if i1<=i0: continue
    S=[[0]*3 for _ in range(3)]; ok=True
    for k in range(i0,i1):
        Sk=kf[k][4]
        if Sk is None: ok=False; break
        J=[[1,0,-(p2[2]-kf[k][2])],[0,1,(p2[1]-kf[k][1])],[0,0,1]]
        JS=mm(mm(J,Sk),tr(J))
        S=[[S[i][j]+JS[i][j] for j in range(3)] for i in range(3)]
    if not ok: continue
    R=[[c,s,0],[-s,c,0],[0,0,1]]
    S=mm(mm(R,S),tr(R))
    Si=inv3(S)
    if Si is None: continue
    q=sum(e[i]*Si[i][j]*e[j] for i in range(3) for j in range(3))
    qs.append(q)
qs.sort()
med=qs[len(qs)//2]
print("relations used", len(qs), "median e'S^-1e", round(med,1), "-> informationScale", round(med/2.366,1), "p25/p75 scale", round(qs[len(qs)//4]/2.366,1), round(qs[3*len(qs)//4]/2.366,1))
