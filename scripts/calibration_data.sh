#!/usr/bin/env bash
# Regenerates the measurements of the shipped calibration example (studies/seed_gear_calibration.cfg):
# the seed gear with four changed strut and tyre parameters (the "true" values below), dropped in its
# limit and light cases and sampled like a drop rig records them, with Gaussian noise from fixed seeds:
#   limit drop: 2 kHz for 0.6 s of the rig's clock, touchdown at t = 0.0173 s (unknown to the fit: it
#               fits t_shift), P_y (sigma 500 N), stroke s and airframe travel h (sigma 0.2 mm each);
#   light drop: 1 kHz for 0.6 s, triggered at touchdown (t_shift = 0 known), P_y (500 N), s (0.2 mm)
#               and the chamber pressure p_1 (sigma 20 kPa; compared, not fitted).
# Seven significant digits, as a rig's logger writes them. Same seeds, same files.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --target synthetic_drop >/dev/null
truth=(--set strut.f1=7.7e-5 --set strut.p01=2.85e6 --set strut.Omega0=1.365e-3 --set tyre.K=8.8e5)
mkdir -p data/drop_tests
build/bin/synthetic_drop data/seed_gear.toml --case limit "${truth[@]}" --rate 2000 --start 0 --end 0.6 \
  --touchdown 0.0173 --seed 1 --digits 7 --channel P_y:Fz_N:500 --channel s:stroke_m:2e-4 --channel h:travel_m:2e-4 \
  --out data/drop_tests/seed_gear_limit.csv
build/bin/synthetic_drop data/seed_gear.toml --case light "${truth[@]}" --rate 1000 --start 0 --end 0.6 \
  --touchdown 0 --seed 2 --digits 7 --channel P_y:Fz_N:500 --channel s:stroke_m:2e-4 --channel p_1:p1_Pa:2e4 \
  --out data/drop_tests/seed_gear_light.csv
