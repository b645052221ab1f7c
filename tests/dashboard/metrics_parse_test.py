"""/metrics of a real tessera-server, read by Prometheus' own Python parser (prometheus_client).

Starts a server on free loopback ports and one worker, renders a small job, then parses /metrics
with prometheus_client.parser and checks the families and their values against the job.
Usage: metrics_parse_test.py BIN_DIR SOURCE_DIR (run with the venv's python, see browser/setup.sh).
"""
import json
import os
import subprocess
import sys
import tempfile
import time
import urllib.request

from prometheus_client.parser import text_string_to_metric_families

PATIENCE_S = 300


def wait_for(what, probe):
    end = time.monotonic() + PATIENCE_S
    while True:
        value = probe()
        if value:
            return value
        if time.monotonic() > end:
            raise SystemExit(f"gave up waiting for {what}")
        time.sleep(0.1)


def main():
    bin_dir, source_dir = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory(prefix="tessera-metrics-") as work:
        children = []
        try:
            log = open(os.path.join(work, "server.log"), "w")
            children.append(subprocess.Popen(
                [os.path.join(bin_dir, "tessera-server"), "--grpc", "127.0.0.1:0",
                 "--port-file", os.path.join(work, "port"), "--http", "127.0.0.1:0",
                 "--http-port-file", os.path.join(work, "http-port"),
                 "--db", os.path.join(work, "farm.db"), "--output-dir", os.path.join(work, "out")],
                stdout=log, stderr=log))
            wait_for("the server", lambda: os.path.exists(os.path.join(work, "port")))
            grpc = "127.0.0.1:" + open(os.path.join(work, "port")).read().strip()
            http = "http://127.0.0.1:" + open(os.path.join(work, "http-port")).read().strip()
            children.append(subprocess.Popen(
                [os.path.join(bin_dir, "tessera-worker"), "--server", grpc, "--threads", "1",
                 "--cache", os.path.join(work, "cache")], stdout=log, stderr=log))
            tiny = os.path.join(source_dir, "tests", "farm", "data", "tiny.json")
            out = subprocess.run(
                [os.path.join(bin_dir, "tessera"), "--server", grpc, "submit", tiny, "--spp", "8",
                 "--batch", "2", "--tile", "8", "--json"], check=True, capture_output=True, text=True)
            job_id = json.loads(out.stdout)["id"]

            def job_done():
                with urllib.request.urlopen(f"{http}/api/jobs/{job_id}") as r:
                    return json.load(r)["state"] == "done"
            wait_for("the job", job_done)

            with urllib.request.urlopen(f"{http}/metrics") as r:
                content_type = r.headers["Content-Type"]
                text = r.read().decode()
            assert content_type.startswith("text/plain; version=0.0.4"), content_type
            families = {f.name: f for f in text_string_to_metric_families(text)}
            print("families:", ", ".join(sorted(f"{n} ({f.type})" for n, f in families.items())))

            def value(family, **labels):
                for s in families[family].samples:
                    if all(s.labels.get(k) == v for k, v in labels.items()):
                        return s.value
                raise AssertionError(f"{family}{labels} missing")

            assert families["tessera_jobs"].type == "gauge"
            assert value("tessera_jobs", state="done") == 1
            assert value("tessera_jobs", state="queued") == 0
            units = 4 * 4  # 16x16 in 8x8 tiles, 8 spp in batches of 2
            assert families["tessera_units_done"].type == "counter"
            assert value("tessera_units_done") == units
            assert value("tessera_units_leased") == 0
            assert value("tessera_units_expired") == 0
            assert value("tessera_results_dropped") == 0
            assert value("tessera_samples_merged") == 16 * 16 * 8
            assert value("tessera_results_received", outcome="accepted") == units
            assert value("tessera_samples_per_second") > 0
            assert value("tessera_workers", state="online") == 1
            # A new store: no check was due, nothing damaged.
            assert families["tessera_store_damaged"].type == "gauge"
            assert value("tessera_store_damaged") == 0
            assert value("tessera_store_check_running") == 0
            assert families["tessera_store_full"].type == "gauge"
            assert value("tessera_store_full") == 0
            latency = families["tessera_merge_latency_seconds"]
            assert latency.type == "histogram"
            buckets = [s for s in latency.samples if s.name.endswith("_bucket")]
            assert buckets[-1].labels["le"] == "+Inf" and buckets[-1].value == units
            counts = [s.value for s in buckets]
            assert counts == sorted(counts), "histogram buckets are cumulative"
            count = [s.value for s in latency.samples if s.name.endswith("_count")]
            assert count == [units], count
            print("1 passed, 0 failed")
        finally:
            for c in children:
                c.terminate()
            for c in children:
                try:
                    c.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    c.kill()


if __name__ == "__main__":
    main()
