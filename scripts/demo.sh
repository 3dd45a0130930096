#!/usr/bin/env bash
# The main job: sets up the machine (idempotent), builds the `wayfinder` command and replays the bundled
# sample walk on the bundled office building, printing the spoken directions with their times.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
swift build -c release --product wayfinder >&2
exec .build/release/wayfinder replay App/Samples/office-walk --map Maps/Buildings/wayfinder-office.json "$@"
