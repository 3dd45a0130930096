#!/usr/bin/env bash
# Checks that every Apple-only source under App/iOS at least parses on Linux (ARKit, SwiftUI, UIKit and
# Core ML do not exist here, so the files cannot be type-checked; `swiftc -parse` catches syntax errors).
set -euo pipefail
cd "$(dirname "$0")/.."
shopt -s globstar nullglob
files=(App/iOS/**/*.swift)
if [ ${#files[@]} -eq 0 ]; then echo "parse-ios: no files under App/iOS"; exit 0; fi
for f in "${files[@]}"; do swiftc -parse "$f"; done
echo "parse-ios: ${#files[@]} files parse"
