import csv,statistics as st,math,sys
def load(p):
    out={}
    for r in csv.DictReader(open(p)):
        out.setdefault((r['mu_s'],r['mu_r']),[]).append(r)
    return out
# python3 xcs_summ.py [DEMCAL_DOE_CSV OTHER_DOE_CSV] (default: the LAMMPS slice of this directory's runs)
d=load(sys.argv[1] if len(sys.argv)>2 else 'xcs/demcal/engine-crosscheck/doe.csv')
l=load(sys.argv[2] if len(sys.argv)>2 else 'xcs/lammps/engine-crosscheck/doe.csv')

for k in d:
    for key in ('angle_of_repose_deg','discharge_t50_s','discharge_time_s','mass_flow_rate_kg_s'):
        a=[float(r[key]) for r in d[k] if r[key] not in ('','nan')]; b=[float(r[key]) for r in l[k] if r[key] not in ('','nan')]
        if len(a)<2 or len(b)<2: print(k,key,a,b); continue
        g=st.mean(b)-st.mean(a); se=math.sqrt(st.variance(a)/len(a)+st.variance(b)/len(b))
        if key=='angle_of_repose_deg':
            print(f"{k} AoR demcal {st.mean(a):.2f}±{st.stdev(a):.2f} other {st.mean(b):.2f}±{st.stdev(b):.2f} gap {g:+.2f} (se {se:.2f})  {[round(x,2) for x in a]} {[round(x,2) for x in b]}")
        else:
            print(f"{k} {key} demcal {st.mean(a):.4g}±{st.stdev(a):.2g} other {st.mean(b):.4g}±{st.stdev(b):.2g} gap {100*g/st.mean(a):+.1f}% (se {100*se/st.mean(a):.1f}%)")
