#!/usr/bin/env bash
# Bounded fuzz campaign (docs/fuzzing.md): runs every wayfinder-fuzz target -- map loader + validator, session
# bundle reader, range CSV, iNavigate importer and its YAML and BMP parts, OCCaM importer -- for a fixed number
# of mutated inputs from the committed seed corpus (Tests/Fuzz/corpus), each input in a supervised child
# process. Fails on any crash, hang (an input running longer than the per-input limit) or property
# violation not on the documented known-crash list (App/Fuzz/KnownCrashes.swift). Deterministic for a seed:
# the inputs are a function of (seed, target, index); the time cap only stops a slow machine early.
# Reproducers and worker logs go to .build/fuzz/<target>/. A self-test runs first: two deliberately
# crashing and hanging targets must be caught (so a broken harness cannot pass silently).
#
# Usage: scripts/fuzz.sh                  (about 2-3 minutes on 2 cores, debug build: what scripts/test.sh runs)
#        FUZZ_EXECS=1000000 FUZZ_SECONDS=3000 FUZZ_CONFIG=release scripts/fuzz.sh   (long campaign)
# Environment: FUZZ_SEED (1), FUZZ_EXECS per target (5000), FUZZ_SECONDS per target (60),
#              FUZZ_TIMEOUT per input in s (10), FUZZ_JOBS targets in parallel (2), FUZZ_CONFIG debug|release,
#              FUZZ_TARGETS comma-separated names or all.
set -euo pipefail
cd "$(dirname "$0")/.."

config=${FUZZ_CONFIG:-debug}
mkdir -p .build/fuzz
if ! swift build -c "$config" --product wayfinder-fuzz >.build/fuzz/build.log 2>&1; then
  cat .build/fuzz/build.log >&2
  echo "fuzz.sh: building wayfinder-fuzz failed" >&2
  exit 1
fi
bin=$(swift build -c "$config" --show-bin-path)/wayfinder-fuzz

# Self-test: the harness must catch a crashing and a hanging target, and the crash reproducer must crash.
self=.build/fuzz/selftest
rm -rf "$self" && mkdir -p "$self"
if "$bin" run --target selftest-crash,selftest-hang --execs 200 --timeout 2 --max-findings 1 --out "$self" >"$self/run.log" 2>&1; then
  cat "$self/run.log" >&2; echo "fuzz.sh: self-test: the harness reported no failure" >&2; exit 1
fi
if ! grep -q "NEW crash in selftest-crash" "$self/run.log" || ! grep -q "NEW hang in selftest-hang" "$self/run.log"; then
  cat "$self/run.log" >&2; echo "fuzz.sh: self-test: a crash or a hang went unnoticed" >&2; exit 1
fi
repro=$(ls "$self"/selftest-crash/crash-*.txt | head -n 1)
if (SWIFT_BACKTRACE=enable=no "$bin" repro --target selftest-crash "$repro"; exit $?) >/dev/null 2>&1; then
  echo "fuzz.sh: self-test: the reproducer $repro did not crash" >&2; exit 1
fi
echo "fuzz.sh: self-test passed (crash and hang caught, reproducer crashes)"

exec "$bin" run \
  --target "${FUZZ_TARGETS:-all}" \
  --seed "${FUZZ_SEED:-1}" \
  --execs "${FUZZ_EXECS:-5000}" \
  --seconds "${FUZZ_SECONDS:-60}" \
  --timeout "${FUZZ_TIMEOUT:-10}" \
  --jobs "${FUZZ_JOBS:-2}" \
  --out .build/fuzz
