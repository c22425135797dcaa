#!/usr/bin/env bash
# Sanitizer builds of the test suite (docs/testing.md, "Sanitizers"):
#
#   tests/sanitize.sh address   AddressSanitizer + UndefinedBehaviorSanitizer: build-asan/,
#                               the core suites (test_core, test_rasterizer, test_texunit),
#                               the trace reader and capture (test_trace), the
#                               programmable profile (test_programmable) and the
#                               golden-trace replays. CI runs this one.
#   tests/sanitize.sh thread    ThreadSanitizer: build-tsan/, the threaded pipeline (the
#                               rasterizer's and the programmable device's fast paths on
#                               several threads: PathsAgree and the device tests) and the
#                               golden replays on 3 threads.
#
# Extra arguments go to every GoogleTest executable (e.g. --gtest_filter=Blend*).
# RETROGLASS_SANITIZE_JOBS sets the build parallelism (default: all cores).
set -euo pipefail
cd "$(dirname "$0")/.."
mode="${1:-address}"
shift || true
case "$mode" in
    address) dir=build-asan; sanitize="address,undefined"; tests=(test_core test_rasterizer test_texunit test_trace test_programmable) ;;
    thread)  dir=build-tsan; sanitize="thread"; tests=(test_rasterizer test_texunit test_programmable) ;;
    *) echo "usage: tests/sanitize.sh address|thread [gtest args]" >&2; exit 2 ;;
esac
say() { printf 'sanitize(%s): %s\n' "$mode" "$*" >&2; }

if [ ! -f "$dir/CMakeCache.txt" ]; then
    gen=()
    command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
    # -g1: line tables and function names, all a sanitizer's stack trace prints; full -g's
    # variable tracking doubled the compile of the largest kernels. -O1: about two thirds
    # of -O2's compile time, the suites about as fast (docs/testing.md, "Sanitizers").
    say "configuring $dir/ (-O1 -g1, -fsanitize=$sanitize)"
    cmake -S . -B "$dir" "${gen[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
        -DRETROGLASS_BENCH=OFF -DRETROGLASS_SANITIZE="$sanitize" >/dev/null
fi
jobs=(); [ -n "${RETROGLASS_SANITIZE_JOBS:-}" ] && jobs=(-j "$RETROGLASS_SANITIZE_JOBS")
say "building ${tests[*]} retroglass_golden"
cmake --build "$dir" "${jobs[@]}" --target "${tests[@]}" retroglass_golden >&2

# Every report is an error: UBSan halts at the first finding instead of printing and going on.
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$PWD/tests/tsan.supp:${TSAN_OPTIONS:-}"
status=0
for t in "${tests[@]}"; do
    filter=()
    [ "$mode" = thread ] && filter=(--gtest_filter='*Paths*:*Device*:*Thread*:*Determinism*:*Batch*')
    say "running $t"
    "$dir/bin/$t" "${filter[@]}" "$@" --gtest_brief=1 || status=1
done
say "replaying the golden traces"
have=" $("$dir/bin/retroglass_golden" list | tr '\n' ' ') "
while read -r name hash _; do
    case "$name" in ''|\#*) continue ;; esac
    if [[ "$have" != *" $name "* ]]; then
        say "skipping golden.$name: a demo's frame, left out of sanitizer builds (-DRETROGLASS_SANITIZE_DEMOS=ON keeps it)"
        continue
    fi
    "$dir/bin/retroglass_golden" check "$name" "tests/golden/$name.trace" "$hash" >/dev/null || {
        say "golden.$name failed: $dir/bin/retroglass_golden check $name tests/golden/$name.trace $hash"
        status=1
    }
done < tests/golden/manifest.txt
[ $status = 0 ] && say "clean" || say "FAILED"
exit $status
