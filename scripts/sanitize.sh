#!/usr/bin/env bash
# The test suite under sanitizers, each in its own build folder:
#   asan   AddressSanitizer + LeakSanitizer + UBSan (every test but those
#          listed in tests/sanitize/asan-skip.txt, with the reason there)
#   tsan   ThreadSanitizer on the C ABI's threaded tests (several contexts
#          on several threads, asynchronous stepping)
#
#   bash scripts/sanitize.sh [asan|tsan|all] [--abi-only] [--json]
#
# --abi-only runs only the C ABI's C tests under ASan (what CI runs). Findings fail the run:
# UBSan does not recover, ASan/LSan/TSan exit non-zero. Suppressions for
# libraries we do not build (PoCL, LLVM inside it, the OpenMP runtime) are in
# tests/sanitize/*.supp, each with the reason; none covers facesr code.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)

which=all abi_only=0 json=0
for a in "$@"; do
  case "$a" in
    asan|tsan|all) which=$a ;;
    --abi-only) abi_only=1 ;;
    --json) json=1 ;;
    *) echo "sanitize.sh: unknown argument '$a' (expected asan|tsan|all, --abi-only, --json)" >&2; exit 2 ;;
  esac
done

bash scripts/install-deps.sh
jobs=$(nproc)
supp=$root/tests/sanitize

configure() {  # folder, sanitizer flags, extra cmake arguments...
  local dir=$1 flags=$2
  shift 2
  # -O1: a sanitized -O3 build of the engine takes twice as long to compile
  # and finds nothing more. NDEBUG as in Release, so the tests see the code
  # that ships. The bindings are left out: mono and cargo load the library
  # into processes that are not sanitized (listed in asan-skip.txt).
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Sanitize \
    -DCMAKE_C_FLAGS_SANITIZE="-O1 -g1 -DNDEBUG" -DCMAKE_CXX_FLAGS_SANITIZE="-O1 -g1 -DNDEBUG" \
    -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" "$@" >/dev/null
}

results=()
asan_flags="-fsanitize=address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
# PoCL's kernel cache starts empty, so that each run compiles the kernels
# in-process as a fresh machine (CI) does, whatever ran before it here.
pocl_cache=$root/out/sanitize-pocl-cache
rm -rf "$pocl_cache" && mkdir -p "$pocl_cache"
asan_vars=(POCL_CACHE_DIR="$pocl_cache" ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:detect_odr_violation=0:strict_string_checks=1:use_sigaltstack=0"
  LSAN_OPTIONS="suppressions=$supp/lsan.supp:print_suppressions=0:use_tls=0"
  UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:suppressions=$supp/ubsan.supp"
  FACESR_TEST_TIME_SCALE=4 OMP_NUM_THREADS=2)

# The ABI's own tests: C programs on libfacesr.so (C99 test, threads, dlopen
# and unload, the C sample both ways). Their build has FACESR_OFFLINE=OFF:
# only the runtime library, libfacesr.so and the C programs are compiled, as
# a game would build them, which also proves the runtime builds without any
# offline dependency. Their rig and model come from the regular build
# (scripts/build.sh, then its capi_test_data fixture): making them is offline
# work.
abi_data=$root/build/capi_test_data
make_abi_data() {
  if [[ ! -f $abi_data/complete.stamp ]]; then
    echo "sanitize: making the ABI test rig and model with the regular build" >&2
    bash scripts/build.sh || return 1
    (cd build && ctest -R '^capi_test_data$' --output-on-failure >/dev/null) || return 1
  fi
}
run_abi() {  # name, build folder, sanitizer flags, ctest regex, then the environment: VAR=value...
  local name=$1 dir=$2 flags=$3 tests=$4
  shift 4
  make_abi_data || return 1
  configure "$dir" "$flags" -DFACESR_OFFLINE=OFF -DFACESR_CAPI_TEST_DATA="$abi_data" || return 1
  echo "sanitize: building the runtime, the C ABI and its C tests in $dir" >&2
  cmake --build "$dir" -j"$jobs" || return 1
  local t0=$SECONDS rc=0
  (cd "$dir" && env "$@" ctest --output-on-failure -j"$jobs" -R "$tests") || rc=$?
  results+=("\"$name\": {\"rc\": $rc, \"seconds\": $((SECONDS - t0))}")
  return $rc
}
asan_abi_tests='^(capi_c|capi_threads|capi_unload|capi_exports|capi_needed_libraries|capi_sample_c_sync|capi_sample_c_async)$'

run_asan() {
  local dir=build-asan
  configure $dir "$asan_flags" -DFACESR_BINDINGS=OFF || return 1
  echo "sanitize: building $dir" >&2
  cmake --build $dir -j"$jobs" || return 1
  local skip
  skip=$(grep -v '^#' "$supp/asan-skip.txt" | awk 'NF {print $1}' | paste -sd'|')
  local t0=$SECONDS rc=0
  (cd $dir && env "${asan_vars[@]}" ctest --output-on-failure -j"$jobs" ${skip:+-E "$skip"}) || rc=$?
  results+=("\"asan\": {\"rc\": $rc, \"seconds\": $((SECONDS - t0))}")
  return $rc
}

# The ABI promises that contexts on different threads are independent and
# that asynchronous stepping is safe: the C tests that do both (four threads
# creating and stepping contexts on one rig and model at once, the C sample
# stepping asynchronously, the C99 test). libgomp is not instrumented, so
# every OpenMP barrier would be a report: one OpenMP thread keeps the reports
# to facesr's own threads and PoCL's.
tsan_env=(TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$supp/tsan.supp"
  FACESR_TEST_TIME_SCALE=4 OMP_NUM_THREADS=1)

status=0
if [[ $which == asan || $which == all ]]; then
  if [[ $abi_only == 1 ]]; then
    run_abi asan_abi build-asan-abi "$asan_flags" "$asan_abi_tests" "${asan_vars[@]}" || status=1
  else
    run_asan || status=1
  fi
fi
if [[ $which == tsan || $which == all ]]; then
  run_abi tsan build-tsan "-fsanitize=thread -fno-omit-frame-pointer" \
    '^(capi_threads|capi_sample_c_async|capi_c)$' "${tsan_env[@]}" || status=1
fi
if [[ $json == 1 ]]; then
  (IFS=,; echo "{\"ok\": $([[ $status == 0 ]] && echo true || echo false), ${results[*]}}")
fi
exit $status
