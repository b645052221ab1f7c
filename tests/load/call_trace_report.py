#!/usr/bin/env python3
"""Where a lease's time goes: joins a tessera-bench-merge --trace run's calls as the simulated
workers saw them (PREFIX-N.client) with the server's call trace (PREFIX-N.server,
server/call_trace.h) by lease id, and prints the percentiles of each part (BENCHMARKS.md,
"Lease latency and capacity").

    tessera-bench-merge --tiles 32 --workers 64 --per-call 16 --units 16384 --trace TRACE_DIR/r
    tests/load/call_trace_report.py TRACE_DIR/r-0
"""
import sys, bisect, collections

def pct(v, p):
    if not v: return float('nan')
    v = sorted(v); k = max(1, -(-len(v) * p // 100)); return v[int(k) - 1]

def summ(name, v, unit=1e6):
    v = [x / unit for x in v]
    print(f"  {name:28s} n={len(v):6d} p50={pct(v,50):8.2f} p90={pct(v,90):8.2f} p99={pct(v,99):8.2f} max={max(v) if v else 0:8.2f} ms")

prefix = sys.argv[1]
client = [l.split() for l in open(prefix + ".client")]
server = [l.split() for l in open(prefix + ".server")]
ev = collections.defaultdict(list)
for k, tid, b, e, a, bb, i in server:
    ev[k].append((int(b), int(e), int(a), int(bb), i, int(tid)))
leases_srv = {x[4]: x for x in ev['lease'] if x[2] > 0}
book_by_tid = collections.defaultdict(list)
for x in ev['book']: book_by_tid[x[5]].append(x)
for v in book_by_tid.values(): v.sort()
rows = []
for k, w, b, e, u, i in client:
    if k != 'lease': continue
    b, e = int(b), int(e)
    s = leases_srv.get(i)
    if not s: continue
    entry, exit_, tid = s[0], s[1], s[5]
    bw = bh = 0
    L = book_by_tid[tid]; j = bisect.bisect_left(L, (entry,))
    if j < len(L) and L[j][0] <= exit_: bw = L[j][1] - L[j][0]; bh = L[j][2]
    rows.append((e - b, entry - b, exit_ - entry, e - exit_, bw, bh, entry, exit_))
print(f"{prefix}: {len(rows)} lease calls with work joined")
summ("client lease", [r[0] for r in rows])
summ("  client -> handler entry", [r[1] for r in rows])
summ("  handler", [r[2] for r in rows])
summ("    book mutex wait", [r[4] for r in rows])
summ("    book mutex hold", [r[5] for r in rows])
summ("  handler exit -> client", [r[3] for r in rows])
thr = pct([r[0] for r in rows], 99)
slow = [r for r in rows if r[0] >= thr]
if slow:
    n = len(slow)
    print(f"  slowest 1% ({n} calls, >= {thr/1e6:.1f} ms): mean in {sum(r[1] for r in slow)/n/1e6:.2f}, handler {sum(r[2] for r in slow)/n/1e6:.2f}, out {sum(r[3] for r in slow)/n/1e6:.2f} ms")
# other server events
for k in ['touch', 'poll', 'upload', 'upload_lock', 'decode', 'commit_wait', 'group_lock', 'group', 'flush']:
    if ev[k]: summ(k, [x[1] - x[0] for x in ev[k]])
if ev['group']:
    calls = [x[2] for x in ev['group']]
    print(f"  calls per group: p50 {pct(calls,50)} p99 {pct(calls,99)} max {max(calls)}; groups {len(calls)}")
if ev['flush']:
    g = [x[2] for x in ev['flush']]
    print(f"  grants per flush: p50 {pct(g,50)} p99 {pct(g,99)} max {max(g)}")
cu = [(int(b), int(e)) for k, w, b, e, u, i in client if k == 'upload']
summ("client upload", [e - b for b, e in cu])
# uploads in server handlers overlapping the slow leases
ups = sorted((x[0], x[1]) for x in ev['upload'])
decs = sorted((x[0], x[1]) for x in ev['decode'])
def overlapping(iv, a, b): return sum(1 for s, e in iv if s < b and e > a)
if slow:
    o = [overlapping(decs, r[6] - r[1], r[6] + r[2] + r[3]) for r in slow[:50]]
    print(f"  decodes overlapping the slow leases' lifetime: mean {sum(o)/len(o):.1f}")
    o2 = [overlapping(decs, r[6] - r[1], r[6] + r[2] + r[3]) for r in rows[::max(1,len(rows)//200)]]
    print(f"  decodes overlapping a typical lease: mean {sum(o2)/len(o2):.1f}")
# when do slow leases happen relative to group ends?
gends = sorted(x[1] for x in ev['group'])
def since_group(t):
    j = bisect.bisect_right(gends, t) - 1
    return (t - gends[j]) / 1e6 if j >= 0 else float('nan')
if slow:
    cb = {}
    print("  slow leases: client start relative to the last group's end (ms):",
          " ".join(f"{since_group(r[6]-r[1]):.0f}" for r in slow))
    allv = [v for v in (since_group(r[6]-r[1]) for r in rows) if v == v]  # nan: before any group
    print(f"  all leases: start after last group end p50 {pct(allv,50):.1f} ms")
    # group commit sizes ending just before slow leases
