"""Runs shell commands in turn, RUNS times after one warm-up round, and prints each one's median
wall time (with the range) and median CPU time (user + system of the child, all threads):
side-by-side timings of whole processes for docs/PERFORMANCE.md.

usage: python3 alternate.py RUNS 'command 1' 'command 2' ...
"""
import subprocess, sys, time, statistics, resource
runs=int(sys.argv[1]); cmds=sys.argv[2:]
wall={c:[] for c in cmds}; cpu={c:[] for c in cmds}
for r in range(runs+1):
    for c in cmds:
        before=resource.getrusage(resource.RUSAGE_CHILDREN)
        t=time.perf_counter(); subprocess.run(c,shell=True,stdout=subprocess.DEVNULL,check=True); dt=time.perf_counter()-t
        after=resource.getrusage(resource.RUSAGE_CHILDREN)
        if r>0:
            wall[c].append(dt*1e3); cpu[c].append((after.ru_utime+after.ru_stime-before.ru_utime-before.ru_stime)*1e3)
for c in cmds:
    w=sorted(wall[c]); print(f"{statistics.median(w):8.1f} ms wall ({w[0]:.1f}..{w[-1]:.1f})  {statistics.median(cpu[c]):8.1f} ms cpu  {c}")
