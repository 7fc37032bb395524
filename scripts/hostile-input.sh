#!/usr/bin/env bash
# Hostile input (issue 9), what CI runs after scripts/test.sh:
#  1. the whole project built with AddressSanitizer and UndefinedBehaviorSanitizer (g++, -O0) in
#     build-asan/, and the unit tests run there;
#  2. the two readers of user files fuzzed with libFuzzer (clang; only the fuzz targets and the
#     solver library are built, in build-fuzz/) for FUZZ_SECONDS each (default 60): the case
#     reader from every case file, the model.h5 reader from meshes of three small cases, both
#     also from fuzz/regressions/.
# A crash stops the script non-zero and leaves the input in build-fuzz/crashes/<target>/; copy it
# into fuzz/regressions/<target>/ so that tests/io/fuzz_regression_test.cpp replays it.
#   scripts/hostile-input.sh
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
jobs=$(nproc)

# 1. Sanitizers on the unit tests (the case tests run in scripts/test.sh's optimised build).
# -O0: the sanitized build then takes ~7 min here instead of ~20. Third-party libraries'
# own faults are not ours: FreeImage (through gmsh) frees with free() what it allocated with
# new, and it, OpenCASCADE, VTK, HDF5 and yaml-cpp keep allocations until exit (fuzz/lsan.supp).
# malloc returns null for a size beyond reason, as glibc's does (HDF5 then fails cleanly).
export ASAN_OPTIONS=alloc_dealloc_mismatch=0:allocator_may_return_null=1:detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
# Without MPI: the unit tests start no MPI job, and Open MPI 4.1 keeps ~120 kB in ~3 400
# allocations past MPI_Finalize (measured with a two-line MPI program under ASan).
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS_RELEASE="-O0" \
  -DSPHFEM_SANITIZE=ON -DSPHFEM_BENCH=OFF -DSPHFEM_MPI=OFF >/dev/null
cmake --build build-asan -j "$jobs"
# Four tests run whole simulations — the two plug tests a perforation (8 min unoptimised), the
# sweep tests two runs each (16 min and more): the release suite has them.
ctest --test-dir build-asan -L unit \
  -E "PostPlug[.](OnATinyPerforation|AProjectileBeyond)|SweepCommand[.](TwoShortRuns|StoppedAndResumed)" \
  -j "$jobs" --output-on-failure

# 2. Fuzzing: a run that really grows past 2 GB or takes 10 s on one input is a finding.
# HDF5 allocates sizes it reads from corrupt metadata (4 GB for a regression input); glibc maps
# such a block lazily, ASan zeroes it (7 s per input, 34 inputs in 30 s). Allocations above 2 GB
# therefore fail (null, which HDF5 reports as an error): 100 inputs per second again.
export ASAN_OPTIONS=alloc_dealloc_mismatch=0:allocator_may_return_null=1:detect_leaks=0:max_allocation_size_mb=2048
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_FLAGS_RELEASE="-O1" -DSPHFEM_FUZZ=ON -DSPHFEM_TESTS=OFF -DSPHFEM_BENCH=OFF \
  -DSPHFEM_MPI=OFF >/dev/null
cmake --build build-fuzz -j "$jobs" --target fuzz_case_reader fuzz_model_h5
corpus=build-fuzz/corpus
rm -rf "$corpus" && mkdir -p "$corpus/case_reader" "$corpus/model_h5"
find cases -name '*.yaml' -exec cp {} "$corpus/case_reader/" \;
cp fuzz/regressions/case_reader/* "$corpus/case_reader/"
for c in bar_pressed_fe bar_pressed_sph bar_impact; do
  build-asan/app/sphfem mesh "cases/$c/case.yaml" -o "build-fuzz/seed_$c" -q
  cp "build-fuzz/seed_$c/model.h5" "$corpus/model_h5/$c.h5"
done
cp fuzz/regressions/model_h5/* "$corpus/model_h5/"
for target in case_reader model_h5; do
  crashes=build-fuzz/crashes/$target
  rm -rf "$crashes" && mkdir -p "$crashes"
  echo "fuzz: $target for ${FUZZ_SECONDS:-60} s"
  log=build-fuzz/fuzz_$target.log
  if ! "build-fuzz/fuzz/fuzz_$target" "$corpus/$target" -max_total_time="${FUZZ_SECONDS:-60}" \
    -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=16384 -artifact_prefix="$crashes/" \
    -print_final_stats=1 2>"$log"; then
    # The whole report (sanitizer's stack, libFuzzer's reason), from its first line on.
    grep -v '^"' "$log" | awk '/ERROR: |runtime error: |Test unit written/ { found = 1 } found'
    echo "fuzz: $target failed; the input is in $crashes:"
    ls -l "$crashes"
    exit 1
  fi
  grep -E "stat::number_of_executed_units" "$log"
done
echo "hostile input: sanitized unit tests and fuzzing passed"
