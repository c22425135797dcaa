#!/usr/bin/env bash
# The golden hashes under GCC and Clang, Debug and Release (docs/testing.md, "Compilers"):
# four build folders (build-gcc-debug, build-gcc-release, build-clang-debug,
# build-clang-release), each building only retroglass_golden, test_trace and
# test_programmable, then every
# golden trace checked against tests/golden/manifest.txt on both paths and 1, 2 and 3
# threads (the programmable binary-search trace of version 2 among them, whose program is
# compiled by each compiler and build type), and the trace tests (capture fidelity, the
# version-2 frame, replays re-recording their traces). Exit status 0 when all four agree
# with the manifest.
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
for cc in gcc clang; do
    for type in Debug Release; do
        dir="build-$cc-$(echo "$type" | tr '[:upper:]' '[:lower:]')"
        if [ "$cc" = gcc ]; then c=gcc; cxx=g++; else c=clang; cxx=clang++; fi
        if [ ! -f "$dir/CMakeCache.txt" ]; then
            gen=(); command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
            cmake -S . -B "$dir" "${gen[@]}" -DCMAKE_BUILD_TYPE="$type" -DCMAKE_C_COMPILER="$c" \
                -DCMAKE_CXX_COMPILER="$cxx" -DRETROGLASS_BENCH=OFF >/dev/null
        fi
        cmake --build "$dir" --target retroglass_golden test_trace test_programmable >&2
        bad=0
        while read -r name hash _; do
            case "$name" in ''|\#*) continue ;; esac
            "$dir/bin/retroglass_golden" check "$name" "tests/golden/$name.trace" "$hash" >/dev/null || {
                echo "compilers: $cc $type: golden.$name differs ($dir/bin/retroglass_golden check $name tests/golden/$name.trace $hash)"
                bad=1
            }
        done < tests/golden/manifest.txt
        "$dir/bin/test_trace" --gtest_brief=1 >/dev/null || { echo "compilers: $cc $type: test_trace failed"; bad=1; }
        # The programmable profile's pinned frame hash (ProgrammablePathsAgree.*Twin*).
        "$dir/bin/test_programmable" --gtest_brief=1 >/dev/null || { echo "compilers: $cc $type: test_programmable failed"; bad=1; }
        [ $bad = 0 ] && echo "compilers: $cc $type: every golden hash holds" || status=1
    done
done
exit $status
