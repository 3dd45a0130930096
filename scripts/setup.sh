#!/usr/bin/env bash
# Idempotent set-up for a fresh Debian machine: system packages (C++ toolchain deps, Eigen, OpenCV with
# dnn/objdetect/calib3d, tesseract with its English model (placard text), GoogleTest, Google Benchmark, CMake, ninja, headless Chromium for report checks)
# and the Python tools used by tests (ONNX Runtime parity check). Safe to run repeatedly; installs only
# what is missing. Nothing here downloads model weights.
set -euo pipefail

APT_PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev
  libopencv-dev libopencv-dnn-dev libopencv-objdetect-dev libopencv-calib3d-dev
  libgtest-dev libbenchmark-dev
  chromium fonts-dejavu-core
  espeak-ng
  libtesseract-dev tesseract-ocr-eng
)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "setup: installing system packages: ${missing[*]}" >&2
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >&2
fi

# Each entry is "import_name[:pip requirement]". OpenCV's Python wheel is pinned below 5: OpenCV 5
# removed cv2.CascadeClassifier, which the sign-detector training tests use.
PY_PACKAGES=(numpy onnx onnxruntime "cv2:opencv-python-headless<5")
py_missing=()
for entry in "${PY_PACKAGES[@]}"; do
  mod="${entry%%:*}"; req="${entry#*:}"
  python3 -c "import $mod" 2>/dev/null || py_missing+=("$req")
done
if [ ${#py_missing[@]} -gt 0 ]; then
  echo "setup: installing Python packages: ${py_missing[*]}" >&2
  python3 -m pip install -q "${py_missing[@]}" >&2
fi
echo "setup: ok" >&2
