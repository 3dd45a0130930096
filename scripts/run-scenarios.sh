#!/usr/bin/env bash
# Simulates every committed scenario (Tests/Scenarios/*.json) on the bundled office and the SKERI floors
# (imported from ../shared/data at run time), replays each through the real pipeline and scores it against
# truth; fails when an aggregate figure is worse than the committed baseline (Tests/Baselines/scenarios.json).
# Then the same for the SKERI convergence study (Tests/ConvergenceStudy: 30 floor-only walks of 30 m or more,
# gate Tests/Baselines/convergence-study.json), and the wrong-start recovery walks (Tests/Recovery: the traveler
# names a start place they are not at; gate Tests/Baselines/recovery.json), and the SKERI floor-change study
# (Tests/FloorChangeStudy: 6 walks that ride the elevator to another floor; gate floor-change-study.json).
# Usage: scripts/run-scenarios.sh [--write-baseline]
set -euo pipefail
cd "$(dirname "$0")/.."
swift build -c release --product wayfinder >&2
shared="${WAYFINDER_SHARED_DATA:-$(cd .. && pwd)/shared/data}"
for suite in "Tests/Scenarios:Tests/Baselines/scenarios.json" "Tests/ConvergenceStudy:Tests/Baselines/convergence-study.json" \
             "Tests/Recovery:Tests/Baselines/recovery.json" "Tests/FloorChangeStudy:Tests/Baselines/floor-change-study.json"; do
  dir="${suite%%:*}"; baseline="${suite#*:}"
  args=(--scenarios "$dir" --skeri "$shared")
  echo "== $dir"
  if [ "${1:-}" = "--write-baseline" ]; then
    .build/release/wayfinder eval "${args[@]}" --write-baseline "$baseline"
  else
    .build/release/wayfinder eval "${args[@]}" --baseline "$baseline"
  fi
done
