#!/usr/bin/env bash
# Bounded fuzz campaign (docs/fuzzing.md): runs every wayfinder-fuzz target -- map loader + validator, session
# bundle reader, range CSV, iNavigate importer and its YAML and BMP parts, OCCaM importer -- for a fixed number
# of mutated inputs from the committed seed corpus (Tests/Fuzz/corpus), each input in a supervised child
# process. Fails on any crash, hang (an input running longer than the per-input limit) or property
# violation not on the documented known-crash list (App/Fuzz/KnownCrashes.swift). Deterministic for a seed:
# the inputs are a function of (seed, target, index); the time cap only stops a slow machine early.
# Reproducers and worker logs go to .build/fuzz/<target>/.
#
# Usage: scripts/fuzz.sh                  (about 2-3 minutes on 2 cores, debug build: what scripts/test.sh runs)
#        FUZZ_EXECS=1000000 FUZZ_SECONDS=3000 FUZZ_CONFIG=release scripts/fuzz.sh   (long campaign)
# Environment: FUZZ_SEED (1), FUZZ_EXECS per target (see below), FUZZ_SECONDS per target (40),
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

exec "$bin" run \
  --target "${FUZZ_TARGETS:-all}" \
  --seed "${FUZZ_SEED:-1}" \
  --execs "${FUZZ_EXECS:-2000}" \
  --seconds "${FUZZ_SECONDS:-40}" \
  --timeout "${FUZZ_TIMEOUT:-10}" \
  --jobs "${FUZZ_JOBS:-2}" \
  --out .build/fuzz
