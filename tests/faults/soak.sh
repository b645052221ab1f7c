#!/usr/bin/env bash
# The soak (outside CI, docs/reliability.md "Soak"): the fault suite's two SIGKILL tests run with
# many rounds until at least WORKER_KILLS worker SIGKILLs and SERVER_KILLS server SIGKILLs have
# landed inside jobs. Every round's job must pass faults::verify_job: done, every unit accepted
# and merged exactly once, pixels bit-identical to `tessera-worker render`. Prints the totals and
# exits non-zero on the first failed round.
#
#   tests/faults/soak.sh BUILD_DIR [WORKER_KILLS=500] [SERVER_KILLS=200]
#
# Each batch of rounds gets its own seed (printed; TESSERA_FAULT_SEED=N replays it).
set -euo pipefail

build=${1:?usage: soak.sh BUILD_DIR [WORKER_KILLS] [SERVER_KILLS]}
want_worker=${2:-500}
want_server=${3:-200}
bin="$build/bin/tessera_fault_tests"
[[ -x "$bin" ]] || { echo "soak.sh: $bin not built (ninja -C $build tessera_fault_tests)" >&2; exit 2; }
log_dir=$(mktemp -d "${TMPDIR:-/tmp}/tessera-soak.XXXXXX")
echo "soak: logs in $log_dir"

# run_until TEST PATTERN WANT: batches of 20 rounds until WANT kills were counted.
run_until() {
  local test=$1 pattern=$2 want=$3 kills=0 rounds=0 batch=0
  while (( kills < want )); do
    local seed=$(( (RANDOM << 15 | RANDOM) + batch ))
    local log="$log_dir/$test-$batch.log"
    if ! TESSERA_FAULT_SEED=$seed TESSERA_FAULT_ROUNDS=20 "$bin" --gtest_filter="Faults.$test" \
        >"$log" 2>&1; then
      echo "soak: $test FAILED (seed $seed), see $log" >&2
      grep -E "FAILED|Failure" "$log" | head -20 >&2
      exit 1
    fi
    local got
    got=$(sed -nE "s/.*\\[faults\\] $pattern: ([0-9]+) rounds, ([0-9]+) .*/\\1 \\2/p" "$log")
    rounds=$(( rounds + ${got% *} ))
    kills=$(( kills + ${got#* } ))
    echo "soak: $test batch $batch seed $seed: total $rounds rounds, $kills kills, 0 failed"
    batch=$(( batch + 1 ))
  done
  echo "soak: $test done: $rounds rounds, $kills SIGKILLs inside jobs, every round verified"
}

run_until WorkersSigkilledAtRandomMomentsOverManyRounds worker-kill "$want_worker"
run_until ServerSigkilledWhileCommittingResultsAndRestarted server-kill "$want_server"
echo "soak: OK (logs in $log_dir)"
