#!/usr/bin/env bash
# Runs every test of the project on Linux: set-up (idempotent), the Swift package's tests, the C++ cores'
# GoogleTest suites (CMake + ctest, which also runs the ONNX Runtime vs OpenCV dnn parity check of the
# committed U-Net, SignDetector.onnx_parity), the parse check of the
# Apple-only sources, and the simulated scenario suite with its regression gate.
# Usage: scripts/test.sh          (from anywhere; CI calls it through .ci/run)
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
jobs=$(nproc 2>/dev/null || echo 2)

bash scripts/setup.sh

echo "== C++ cores: CMake build + GoogleTest (ctest)"
cmake -S . -B build/cmake -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/cmake -j "$jobs"
ctest --test-dir build/cmake --output-on-failure -j "$jobs"

echo "== Swift package: build + XCTest"
swift build -j "$jobs"
swift test -j "$jobs" --parallel --num-workers "$jobs"

echo "== Fuzz campaign (bounded, scripts/fuzz.sh)"
bash scripts/fuzz.sh

echo "== Apple-only sources parse (swiftc -parse)"
bash scripts/parse-ios.sh

if [ -x scripts/run-scenarios.sh ]; then
  echo "== Scenario suite (simulated walks, regression gate)"
  bash scripts/run-scenarios.sh
fi
echo "== all tests passed"
