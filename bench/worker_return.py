#!/usr/bin/env python3
"""How soon workers come back after the server restarts (docs/farm.md, "Server restart").

Starts tessera-server and two idle one-thread workers on loopback, then ROUNDS times: stops the
server (SIGTERM), waits DOWN seconds, starts it again on the same ports with its call trace on
(TESSERA_CALL_TRACE, server/call_trace.h) and reports, from the moment its port file appears:
when a `tessera list` is first answered, and when the workers' first LeaseUnit calls reached it
(the trace's "lease" events; CLOCK_MONOTONIC on both sides).

  bench/worker_return.py BIN_DIR DOWN_SECONDS [ROUNDS]     # BIN_DIR: build/bin
"""
import os
import signal
import socket
import subprocess
import sys
import tempfile
import time


def free_port():
    s = socket.socket()
    s.bind(("127.0.0.1", 0))
    port = s.getsockname()[1]
    s.close()
    return port


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    bindir, down = sys.argv[1], float(sys.argv[2])
    rounds = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    work = tempfile.mkdtemp(prefix="worker-return-")
    grpc_port, http_port = free_port(), free_port()
    log = open(os.path.join(work, "server.log"), "a")

    def start_server(trace=None):
        port_file = os.path.join(work, "port")
        if os.path.exists(port_file):
            os.remove(port_file)
        env = dict(os.environ)
        if trace:
            env["TESSERA_CALL_TRACE"] = trace
        server = subprocess.Popen(
            [f"{bindir}/tessera-server", "--grpc", f"127.0.0.1:{grpc_port}", "--http",
             f"127.0.0.1:{http_port}", "--db", os.path.join(work, "farm.db"), "--port-file",
             port_file, "--output-dir", os.path.join(work, "out")],
            stdout=log, stderr=subprocess.STDOUT, env=env)
        while not os.path.exists(port_file) or os.path.getsize(port_file) == 0:
            if server.poll() is not None:
                sys.exit(f"tessera-server exited; see {work}/server.log")
            time.sleep(0.002)
        return server, time.monotonic()

    server, _ = start_server()
    workers = [subprocess.Popen(
        [f"{bindir}/tessera-worker", "--server", f"127.0.0.1:{grpc_port}", "--threads", "1",
         "--cache", os.path.join(work, f"cache{i}")],
        stdout=open(os.path.join(work, f"worker{i}.log"), "w"), stderr=subprocess.STDOUT)
        for i in range(2)]
    time.sleep(3)
    for r in range(rounds):
        server.send_signal(signal.SIGTERM)
        server.wait()
        time.sleep(down)
        trace = os.path.join(work, f"trace{r}")
        server, listening = start_server(trace)
        answered = None
        while answered is None:
            done = subprocess.run([f"{bindir}/tessera", "--server", f"127.0.0.1:{grpc_port}", "list"],
                                  capture_output=True)
            if done.returncode == 0:
                answered = time.monotonic() - listening
        time.sleep(8)
        server.send_signal(signal.SIGTERM)
        server.wait()
        with open(trace) as f:
            leases = sorted(int(line.split()[2]) for line in f if line.startswith("lease "))
        print(f"round {r}: first list answered {answered:.2f} s after listening; "
              f"first two lease calls {', '.join(f'{b / 1e9 - listening:.2f}' for b in leases[:2])} s")
        server, _ = start_server()
        time.sleep(3)
    for w in workers:
        w.send_signal(signal.SIGTERM)
    for w in workers:
        w.wait()
    server.send_signal(signal.SIGTERM)
    server.wait()
    print(f"logs in {work}")


if __name__ == "__main__":
    main()
