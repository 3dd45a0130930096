#!/usr/bin/env bash
# End to end with the detectors (issue 16): simulates walks of the SKERI convergence study with camera images
# (the simulator's 640 x 480 renders, one image per detection opportunity), then scores the same bundles three
# ways with `wayfinder eval`: the simulator's recorded sightings, the cascade on the images and the U-Net on
# the images. Prints the three score tables; docs/benchmarks.md "End to end with the detectors" has the figures.
# Usage: scripts/detector-e2e-study.sh [OUT_DIR] [WALK...]   (default /tmp/wf-e2e and six study walks)
# Takes about 15 min on one core (rendering is most of it).
set -euo pipefail
cd "$(dirname "$0")/.."
out="${1:-/tmp/wf-e2e}"; shift || true
walks=("$@")
[ ${#walks[@]} -gt 0 ] || walks=(conv-2-01 conv-2-04 conv-3-04 conv-3-06 conv-4-00 conv-4-03)
swift build -c release --product wayfinder >&2
mkdir -p "$out"
bundles=()
for w in "${walks[@]}"; do
  b="$out/$w"
  if [ ! -f "$b/truth.jsonl" ]; then
    .build/release/wayfinder simulate --scenario "Tests/ConvergenceStudy/$w.json" --images --image-rate 10 -o "$b" --overwrite >&2
  fi
  bundles+=("$b")
done
for d in recorded cascade unet; do
  echo "== sightings: $d"
  .build/release/wayfinder eval "${bundles[@]}" --map skeri --detector "$d"
done
