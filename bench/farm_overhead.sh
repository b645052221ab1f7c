#!/usr/bin/env bash
# The farm's overhead (BENCHMARKS.md): the same job rendered by `tessera-worker render` and by
# tessera-server + one tessera-worker on the same machine, RUNS times each, alternating (the
# order flips every run); prints the medians of wall time and of CPU time, the overhead by both,
# the units per job and the result bytes per unit, and checks that every farm image has the
# local image's pixels bit for bit (idiff).
#
#   bench/farm_overhead.sh                          # 512x512, 256 spp Cornell box, 5 runs each
#   BATCH=256 bench/farm_overhead.sh                # the same job with fixed 256-spp batches
#   SCENE=scenes/hexroom.json bench/farm_overhead.sh
#   RUNS=3 SIZE=256 SPP=64 bench/farm_overhead.sh
#   BIN=/path/to/build/bin bench/farm_overhead.sh   # another build's binaries
#   LOCAL=0 bench/farm_overhead.sh                  # farm runs only: the server's and client's
#                                                   # CPU per job, without the local renders
#
# Wall time of the farm run: `tessera submit -o OUT.exr` from submission to the image on disk
# (bundle upload, scheduling, every unit's round trip, merge, EXR+PNG written by the server,
# EXR downloaded). The local run: `tessera-worker render -o OUT.exr`, process start to exit.
#
# CPU time (user + system, every thread, including threads that have ended): the local run's
# from wait4() on the process; the farm's is the server's and the worker's utime + stime
# (/proc/PID/stat) at the end of the submit minus at its start, plus the client's own (wait4).
# On a busy shared machine the wall times carry everyone else's load while the CPU seconds
# carry only ours (cache and frequency effects aside), so the CPU overhead is the figure to
# read there. Run i uses seed SEED0 + i on both sides: every farm job is a new job, whose
# renderer the worker builds (as the local run does), and each pair must match bit for bit.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
export BIN="${BIN:-$ROOT/build/bin}"
export RUNS="${RUNS:-5}"
export SIZE="${SIZE:-512}"
export SPP="${SPP:-256}"
export BATCH="${BATCH:-}"
export SEED0="${SEED0:-1}"
export LOCAL="${LOCAL:-1}"
export SCENE="${SCENE:-$ROOT/scenes/cornell.json}"

for b in tessera-server tessera-worker tessera; do
  [ -x "$BIN/$b" ] || { echo "farm_overhead: $BIN/$b not built (set BIN)" >&2; exit 1; }
done
command -v idiff >/dev/null || { echo "farm_overhead: idiff (OpenImageIO's tools) not found" >&2; exit 1; }
[[ "$LOCAL" =~ ^[01]$ ]] || { echo "farm_overhead: LOCAL must be 0 or 1 (got '$LOCAL')" >&2; exit 1; }
[ -z "$BATCH" ] || [[ "$BATCH" =~ ^[1-9][0-9]*$ ]] ||
  { echo "farm_overhead: BATCH must be a positive integer (got '$BATCH')" >&2; exit 1; }

WORK="$(mktemp -d)"
export WORK
trap 'rm -rf "$WORK"' EXIT

python3 - <<'PY'
import json, os, re, signal, statistics, subprocess, sys, time

BIN, WORK, SCENE = os.environ["BIN"], os.environ["WORK"], os.environ["SCENE"]
RUNS, SIZE, SPP = int(os.environ["RUNS"]), os.environ["SIZE"], os.environ["SPP"]
BATCH, SEED0 = os.environ["BATCH"], int(os.environ["SEED0"])
LOCAL = os.environ["LOCAL"] == "1"
TICK = os.sysconf("SC_CLK_TCK")
running = []  # the child run_child waits for, ended with us

def terminated(*_):
    for p in running:
        p.kill()
    sys.exit("farm_overhead: terminated")  # runs `finally`: the server and worker stop

signal.signal(signal.SIGTERM, terminated)

def job_options(seed):
    opts = ["--width", SIZE, "--height", SIZE, "--spp", SPP, "--seed", str(seed)]
    return opts + (["--batch", BATCH] if BATCH else [])

def proc_written(pid):
    """Bytes pid has written through write(2) and its kind (wchar of /proc/PID/io): files and
    sockets, whether or not they reach the disk."""
    with open(f"/proc/{pid}/io") as f:
        return next(int(l.split()[1]) for l in f if l.startswith("wchar:"))

def proc_cpu(pid):
    """utime + stime of every thread of pid, ended ones included, in seconds (/proc/PID/stat)."""
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / TICK  # fields 14 and 15 of proc(5)

def run_child(argv, **kw):
    """Runs argv to its end; (wall s, user + sys s of the child and its children)."""
    t0 = time.monotonic()
    p = subprocess.Popen(argv, **kw)
    running.append(p)
    _, status, usage = os.wait4(p.pid, 0)
    running.remove(p)
    wall = time.monotonic() - t0
    p.returncode = os.waitstatus_to_exitcode(status)
    if p.returncode != 0:
        sys.exit(f"farm_overhead: {' '.join(argv)} exited {p.returncode}")
    return wall, usage.ru_utime + usage.ru_stime

log = lambda name: open(os.path.join(WORK, name), "w")
server = subprocess.Popen(
    [f"{BIN}/tessera-server", "--grpc", "127.0.0.1:0", "--http", "127.0.0.1:0",
     "--port-file", f"{WORK}/port", "--db", f"{WORK}/farm.db", "--output-dir", f"{WORK}/outputs"],
    stdout=log("server.log"), stderr=subprocess.STDOUT)
for _ in range(600):
    if os.path.exists(f"{WORK}/port") and os.path.getsize(f"{WORK}/port") > 0:
        break
    time.sleep(0.05)
addr = "127.0.0.1:" + open(f"{WORK}/port").read().strip()
worker = subprocess.Popen(
    [f"{BIN}/tessera-worker", "--server", addr, "--cache", f"{WORK}/cache", "--name", "bench"],
    stdout=log("worker.log"), stderr=subprocess.STDOUT)

rows = []  # per run: local wall, local cpu, farm wall, farm cpu (server, worker, client)
try:
    for i in range(RUNS):
        seed = SEED0 + i
        local_exr, farm_exr = f"{WORK}/local{i}.exr", f"{WORK}/farm{i}.exr"
        def local():
            return run_child([f"{BIN}/tessera-worker", "render", SCENE, *job_options(seed), "-q",
                              "-o", local_exr], stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL)
        def farm():
            s0, w0, b0 = proc_cpu(server.pid), proc_cpu(worker.pid), proc_written(server.pid)
            wall, client = run_child([f"{BIN}/tessera", "--server", addr, "submit", SCENE,
                                      *job_options(seed), "-o", farm_exr],
                                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            return (wall, proc_cpu(server.pid) - s0, proc_cpu(worker.pid) - w0, client,
                    proc_written(server.pid) - b0)
        if not LOCAL:
            fw, fs, fwk, fcl, fb = farm()
            lw = lc = float("nan")
        elif i % 2 == 0:
            lw, lc = local(); fw, fs, fwk, fcl, fb = farm()
        else:
            fw, fs, fwk, fcl, fb = farm(); lw, lc = local()
        same = not LOCAL or subprocess.run(
            ["idiff", "-fail", "0", "-warn", "0", farm_exr, local_exr],
            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode == 0
        rows.append((lw, lc, fw, fs + fwk + fcl, fs, fwk, fcl, same, fb / 1e6))
        print(f"run {i + 1} (seed {seed}): local {lw:.2f} s wall, {lc:.2f} s CPU; farm {fw:.2f} s "
              f"wall, {fs + fwk + fcl:.2f} s CPU (server {fs:.2f}, worker {fwk:.2f}, client "
              f"{fcl:.2f}), server wrote {fb / 1e6:.1f} MB; pixels "
              f"{'not compared' if not LOCAL else 'identical' if same else 'DIFFER'}",
              file=sys.stderr, flush=True)
        if LOCAL:
            os.remove(local_exr)
        os.remove(farm_exr)
    status = subprocess.run([f"{BIN}/tessera", "--server", addr, "status", "1", "--json"],
                            capture_output=True, text=True, check=True)
    units = json.loads(status.stdout)["counters"]["units_total"]
finally:
    worker.send_signal(signal.SIGTERM)
    worker.wait()
    server.send_signal(signal.SIGTERM)
    server.wait()

found = re.findall(r"\((\d+) per unit\)", open(f"{WORK}/worker.log").read())
per_unit = found[-1] if found else "?"
med = lambda k: statistics.median(r[k] for r in rows)
lw, lc, fw, fc = med(0), med(1), med(2), med(3)
runs = lambda k: " ".join(f"{r[k]:.2f}" for r in rows)
schedule = f"fixed batches of {BATCH} spp" if BATCH else "progressive (default) schedule"
print(f"job: {os.path.basename(SCENE)} {SIZE}x{SIZE}, {SPP} spp, {schedule}; {units} units per "
      f"job, {RUNS} runs each, alternating")
if LOCAL:
    print(f"tessera-worker render : wall median {lw:.2f} s ({runs(0)}); CPU median {lc:.2f} s ({runs(1)})")
print(f"server + 1 worker     : wall median {fw:.2f} s ({runs(2)}); CPU median {fc:.2f} s ({runs(3)})")
print(f"  CPU medians by process: server {med(4):.2f} s, worker {med(5):.2f} s, client {med(6):.2f} s"
      f"; server wrote {med(8):.1f} MB per job (median; {runs(8)})")
if LOCAL:
    print(f"farm overhead         : wall {100 * (fw - lw) / lw:+.2f} %, CPU "
          f"{100 * (fc - lc) / lc:+.2f} % (medians); CPU per pair: "
          + " ".join(f"{100 * (r[3] - r[1]) / r[1]:+.2f}" for r in rows) + " %")
print(f"result bytes per unit : {per_unit} (zstd-compressed accumulation, gRPC framing excluded)")
print(f"farm = local pixels   : {sum(r[7] for r in rows)} of {RUNS} runs"
      + ("" if LOCAL else " (LOCAL=0: no local render, nothing compared)"))
if not all(r[7] for r in rows):
    sys.exit(1)
PY
