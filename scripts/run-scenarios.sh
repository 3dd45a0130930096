#!/usr/bin/env bash
# Simulates every committed scenario (Tests/Scenarios/*.json) on the bundled office and the SKERI floors
# (imported from ../shared/data at run time), replays each through the real pipeline and scores it against
# truth; fails when an aggregate figure is worse than the committed baseline (Tests/Baselines/scenarios.json).
# Usage: scripts/run-scenarios.sh [--write-baseline]
set -euo pipefail
cd "$(dirname "$0")/.."
swift build -c release --product wayfinder >&2
shared="${WAYFINDER_SHARED_DATA:-$(cd .. && pwd)/shared/data}"
args=(--scenarios Tests/Scenarios --skeri "$shared")
if [ "${1:-}" = "--write-baseline" ]; then
  .build/release/wayfinder eval "${args[@]}" --write-baseline Tests/Baselines/scenarios.json
else
  .build/release/wayfinder eval "${args[@]}" --baseline Tests/Baselines/scenarios.json
fi
