"""The main job's runs side by side from their series.csv: the front [m] and the running peak of the dam's force
[N] at a few times, then each run's peak, its time, the final front, the steps and the static load (the force's
mean over 2.4-2.5 s) (docs/pore-water.md, The semi-implicit step).

    python benchmarks/pore_water/twin_compare.py LABEL=SERIES_CSV [LABEL=SERIES_CSV ...]
"""
import csv, sys, numpy as np
def load(f):
    rows=list(csv.DictReader(open(f)))
    t=np.array([float(r["time"]) for r in rows]); F=np.array([np.sqrt(sum(float(r[f"dam_f{a}"])**2 for a in "xyz")) for r in rows])
    fx=np.array([float(r["front_x"]) for r in rows]); st=np.array([float(r["step"]) for r in rows])
    return t,F,fx,st
runs={k:load(v) for k,v in [a.split("=") for a in sys.argv[1:]]}
print("t", *runs.keys())
for T in (0.4,0.8,1.0,1.2,1.5,2.0,2.5):
    line=[f"{T:.1f}"]
    for k,(t,F,fx,st) in runs.items():
        i=np.searchsorted(t,T-1e-9); i=min(i,len(t)-1)
        line.append(f"front {fx[i]:.3f} F {F[t<=T+1e-9].max():.0f}")
    print(" | ".join(line))
for k,(t,F,fx,st) in runs.items():
    k2=int(np.argmax(F)); print(k, "peak", round(F[k2]), "at", t[k2], "final front", fx[-1], "steps", st[-1], "static load (2.4-2.5 s mean)", round(F[t>2.4].mean()))
