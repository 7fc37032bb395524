#!/usr/bin/env bash
# Sets up, builds and runs the main job into out/<case>, then says where the ParaView file, the
# summary and the report are. Without arguments the main job is one shot of Børvik's perforation
# test (cases/borvik_12mm, 303.5 m/s, quarter model, coarse preset); with arguments it runs
# `sphfem run CASE.yaml [--set key=value …]`.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -eq 0 ]; then
  set -- cases/borvik_12mm/case.yaml --set preset=coarse
fi
case_file=$1
shift
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target sphfem
name=$(basename "$(dirname "$case_file")")
./build/app/sphfem run "$case_file" -o "out/$name" "$@"
