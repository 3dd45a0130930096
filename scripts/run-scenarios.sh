#!/usr/bin/env bash
# Simulates every committed scenario (Tests/Scenarios/*.json) on the bundled office and the SKERI floors
# (imported from ../shared/data at run time), replays each through the real pipeline and scores it against
# truth; fails when an aggregate figure is worse than the committed baseline (Tests/Baselines/scenarios.json).
# Then the same for the SKERI convergence study (Tests/ConvergenceStudy: 30 floor-only walks of 30 m or more,
# gate Tests/Baselines/convergence-study.json), and the wrong-start recovery walks (Tests/Recovery: the traveler
# names a start place they are not at; gate Tests/Baselines/recovery.json), and the SKERI floor-change study
# (Tests/FloorChangeStudy: 6 walks that ride the elevator to another floor; gate floor-change-study.json).
# Last, two stress runs behind the real detectors' errors measured on real photos (`--sim-detector`,
# DetectorParameters.realPhotoUNet / .realPhotoCascade; docs/benchmarks.md "Behind the real detectors' errors"):
# the convergence study behind the U-Net's (gate convergence-study-real-unet.json) and the scenario suite behind
# the unrefined cascade's (gate scenarios-real-cascade.json: its -25 % range bias caused wrong locks until the
# thirty-first stop's thin-rival rule removed the last, and the gate now holds them at 0); and the scenario suite
# behind that cascade's recall and false positives with a -15 % range bias (`--sim-range-bias -0.15`, gate
# scenarios-cascade-bias-15.json: the bias the localizer's range-bias term holds with no wrong lock,
# docs/benchmarks.md "Seventh stop"). And the
# scenario suite and the convergence study with the compass ignored (`--no-compass`, gates
# scenarios-no-compass.json and convergence-study-no-compass.json): issue 15 asks for no confidently-wrong lock
# with the compass absent too (older recordings, a phone without a usable compass). Only the SKERI walks change:
# the office map has no north, so its walks never use the compass. Last, the scenario suite with filter seeds 2
# and 3 and the convergence study with seed 2 (`--seed`; gates scenarios-seed-2.json, scenarios-seed-3.json,
# convergence-study-seed-2.json): every other gate replays with seed 1, and a wrong lock that one seed happens
# to avoid (the office's turned twin locked in 5 of 8 seeds but not in seed 1, docs/benchmarks.md "Eighth stop")
# must not pass unseen. Last, two runs behind rougher noise models than the simulator's own (`--sim-params`,
# Tests/StressProfiles, docs/benchmarks.md "Eleventh stop"): the convergence study with every model rough at once
# (gate convergence-study-all-rough.json) and the scenario suite behind rough VIO (relocalization snaps, larger
# scale and yaw drift; gate scenarios-vio-rough.json): a figure that holds only on our own noise models is not the
# figure. Last, the convergence study behind the unrefined cascade's 0.06 false positives per frame scored like its
# signs (Tests/StressProfiles/scores-uninformative.json, gate convergence-study-cascade-scores-uninformative.json):
# the real detectors' scores do not tell false positives apart, and one-frame false sightings must not lock the
# filter on a look-alike place (App/Core/SightingCorroboration.swift, docs/benchmarks.md "Twenty-fourth stop").
# Last, the convergence study on a map that is wrong (Tests/StressProfiles/survey-rough.json, gate
# convergence-study-survey-rough.json): signs hang 0.3 m along their walls from where the map says, each has its own
# size, walls stand 0.15 m off (App/Simulation/SurveyErrors.swift, docs/benchmarks.md "Twenty-seventh stop").
# Last, the scenario suite behind every rough model at once (gate scenarios-all-rough.json, thirtieth stop): a wrong
# lock there (office-long-many-turns, a quarter-turned pose held 15 m) went unseen from the twenty-sixth stop until
# the thirtieth, which removed it (more particles while not localized; docs/benchmarks.md "Thirtieth stop").
# Last, the two runs in which the thirty-fourth stop's seed sweep found wrong locks (the same walk, a hypothesis
# outside the building locked after 10 s of unexplained sightings): the scenario suite behind all-rough with filter
# seed 11 (gate scenarios-all-rough-seed-11.json) and behind look-alikes with seed 9 (gate
# scenarios-look-alikes-seed-9.json); the lock's 4 s look back at the sightings removed both
# (docs/benchmarks.md "Thirty-fourth stop"); since the thirty-fifth stop the floor's footprint keeps such hypotheses
# inside the building too, and scenarios-all-rough.json allows 1 missing instruction (earlier locks on the
# symmetric office break when the twin gets ahead; the six-seed measurement is in docs/benchmarks.md "Thirty-fifth
# stop"). A FLAG field may hold several flags, separated by spaces.
# Usage: scripts/run-scenarios.sh [--write-baseline]
set -euo pipefail
cd "$(dirname "$0")/.."
swift build -c release --product wayfinder >&2
shared="${WAYFINDER_SHARED_DATA:-$(cd .. && pwd)/shared/data}"
for suite in "Tests/Scenarios:Tests/Baselines/scenarios.json" "Tests/ConvergenceStudy:Tests/Baselines/convergence-study.json" \
             "Tests/Recovery:Tests/Baselines/recovery.json" "Tests/FloorChangeStudy:Tests/Baselines/floor-change-study.json" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-real-unet.json:real-unet" \
             "Tests/Scenarios:Tests/Baselines/scenarios-real-cascade.json:real-cascade" \
             "Tests/Scenarios:Tests/Baselines/scenarios-cascade-bias-15.json:real-cascade:-0.15" \
             "Tests/Scenarios:Tests/Baselines/scenarios-no-compass.json:::--no-compass" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-no-compass.json:::--no-compass" \
             "Tests/Scenarios:Tests/Baselines/scenarios-seed-2.json:::--seed=2" \
             "Tests/Scenarios:Tests/Baselines/scenarios-seed-3.json:::--seed=3" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-seed-2.json:::--seed=2" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-all-rough.json:::--sim-params=Tests/StressProfiles/all-rough.json" \
             "Tests/Scenarios:Tests/Baselines/scenarios-vio-rough.json:::--sim-params=Tests/StressProfiles/vio-rough.json" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-cascade-scores-uninformative.json:real-cascade::--sim-params=Tests/StressProfiles/scores-uninformative.json" \
             "Tests/ConvergenceStudy:Tests/Baselines/convergence-study-survey-rough.json:::--sim-params=Tests/StressProfiles/survey-rough.json" \
             "Tests/Scenarios:Tests/Baselines/scenarios-all-rough.json:::--sim-params=Tests/StressProfiles/all-rough.json" \
             "Tests/Scenarios:Tests/Baselines/scenarios-all-rough-seed-11.json:::--sim-params=Tests/StressProfiles/all-rough.json --seed=11" \
             "Tests/Scenarios:Tests/Baselines/scenarios-look-alikes-seed-9.json:::--sim-params=Tests/StressProfiles/look-alikes.json --seed=9"; do
  IFS=: read -r dir baseline detector bias flag <<<"$suite"
  args=(--scenarios "$dir" --skeri "$shared")
  if [ -n "$detector" ]; then args+=(--sim-detector "$detector"); fi
  if [ -n "$bias" ]; then args+=("--sim-range-bias=$bias"); fi
  if [ -n "$flag" ]; then read -r -a flags <<<"$flag"; args+=("${flags[@]}"); fi
  echo "== $dir${detector:+ (behind the $detector detector${bias:+, range bias $bias})}${flag:+ ($flag)}"
  if [ "${1:-}" = "--write-baseline" ]; then
    .build/release/wayfinder eval "${args[@]}" --write-baseline "$baseline"
  else
    .build/release/wayfinder eval "${args[@]}" --baseline "$baseline"
  fi
done
