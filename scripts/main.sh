#!/usr/bin/env bash
# The main job on the shipped default: installs what is missing, builds, and runs the design study
# of the reference gear (minimise the limit-case peak load subject to its Part 25 certification matrix,
# every case of the scene and the matrix re-checked and reported).
# Extra arguments go to `optimize` (e.g. --threads 2, --out DIR).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$jobs" --target optimize simulate certify
build/bin/optimize studies/seed_gear_min_peak.cfg --out out/seed_gear_min_peak --plots "$@"
