#!/usr/bin/env bash
# The main job: sets up the machine (idempotent), builds the `wayfinder` command and replays the bundled
# sample walk on the bundled office building, printing the spoken directions with their times, and writes
# what the traveler heard and felt (espeak-ng speech and haptic ticks on the walk's timeline) to
# build/demo/walk.wav (WAYFINDER_DEMO_WAV overrides the path). Extra arguments go to `wayfinder replay`
# (e.g. --speak to hear it live, --clock-face, --units steps, --language es).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
swift build -c release --product wayfinder >&2
wav="${WAYFINDER_DEMO_WAV:-build/demo/walk.wav}"
mkdir -p "$(dirname "$wav")"
exec .build/release/wayfinder replay App/Samples/office-walk --map Maps/Buildings/wayfinder-office.json --audio "$wav" "$@"
