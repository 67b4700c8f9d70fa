import json,sys,glob,statistics as st,math
n=sys.argv[1]
def get(p):
    out={}
    for f in sorted(glob.glob(f"{n}/{p}*/run.json")):
        o=json.load(open(f))["observables"]; out[f.split('/')[-2]]=o
    return out
d=get('d'); l=get('l')
for key in ("angle_of_repose_deg","discharge_time_s"):
    a=[o.get(key) for o in d.values() if o.get(key) is not None]; b=[o.get(key) for o in l.values() if o.get(key) is not None]
    if len(a)<2 or len(b)<2: print(key,a,b); continue
    g=st.mean(b)-st.mean(a); se=math.sqrt(st.variance(a)/len(a)+st.variance(b)/len(b))
    print(f"{n} {key}: demcal {st.mean(a):.3f} (se {st.stdev(a)/math.sqrt(len(a)):.3f}, n={len(a)}) lammps {st.mean(b):.3f} (se {st.stdev(b)/math.sqrt(len(b)):.3f}, n={len(b)}) gap {g:+.3f} se {se:.3f}")
    print("   demcal", [round(x,2) for x in a]); print("   lammps",[round(x,2) for x in b])
