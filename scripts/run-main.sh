#!/usr/bin/env bash
# Sets up, builds and runs the main job (today the paper's FE reference bar) into out/<case>,
# then says where the ParaView file and the summary are.
set -euo pipefail
cd "$(dirname "$0")/.."
case_file=${1:-cases/bar_pressed_fe/case.yaml}
bash scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j "$(nproc)" --target sphfem
name=$(basename "$(dirname "$case_file")")
./build/app/sphfem run "$case_file" -o "out/$name"
