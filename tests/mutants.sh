#!/usr/bin/env bash
# The mutation check (issue 24 item 4; docs/testing.md, "Mutants"): each plausible one-line
# bug of tests/mutants.txt is applied alone, the test binaries its line names are rebuilt
# and run, and the bug is restored. A mutant is killed when a test fails; the report names
# the tests that failed (each names its stage: Suite.Test), or SURVIVED.
#
#   tests/mutants.sh [ID ...]        every mutant, or the named ones
# Environment: MUTANTS_BUILD_DIR (default build-mutants), a Release build of its own so the
# developer's build/ is not touched. Outside the default suite: it rebuilds once per mutant
# (about a minute each on 2 cores). Exit status 0 when every mutant was killed.
set -uo pipefail
cd "$(dirname "$0")/.."
build="${MUTANTS_BUILD_DIR:-build-mutants}"
list=tests/mutants.txt
sep=' ␞ '

if [ ! -f "$build/CMakeCache.txt" ]; then
    gen=(); command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
    cmake -S . -B "$build" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DRETROGLASS_BENCH=OFF >/dev/null || exit 2
fi

report=$(mktemp)
backup=$(mktemp)
restore() { [ -n "${file:-}" ] && [ -s "$backup" ] && cp "$backup" "$file"; }
trap 'restore; rm -f "$backup" "$report"' EXIT INT TERM

killed=0 survived=0 broken=0
while IFS= read -r line; do
    case "$line" in ''|\#*) continue ;; esac
    id=${line%%"$sep"*}; rest=${line#*"$sep"}
    stage=${rest%%"$sep"*}; rest=${rest#*"$sep"}
    file=${rest%%"$sep"*}; rest=${rest#*"$sep"}
    original=${rest%%"$sep"*}; rest=${rest#*"$sep"}
    mutated=${rest%%"$sep"*}; binaries=${rest#*"$sep"}
    if [ $# -gt 0 ] && [[ " $* " != *" $id "* ]]; then file=; continue; fi
    count=$(ORIG="$original" perl -0ne '$n = () = /\Q$ENV{ORIG}\E/g; print $n' "$file")
    if [ "$count" != 1 ]; then
        printf '%-22s BROKEN: the original text occurs %s times in %s\n' "$id" "$count" "$file" | tee -a "$report"
        broken=$((broken + 1)); file=; continue
    fi
    cp "$file" "$backup"
    ORIG="$original" MUT="$mutated" perl -0pi -e 's/\Q$ENV{ORIG}\E/$ENV{MUT}/' "$file"
    failed=
    # shellcheck disable=SC2086
    if ! cmake --build "$build" --target $binaries >/dev/null 2>&1; then
        failed="(does not compile)"
    else
        for b in $binaries; do
            out=$("$build/bin/$b" --gtest_brief=1 2>&1)
            rc=$?
            # Suite.Test, parameterised ones as Prefix/Suite.Test/Param.
            names=$(echo "$out" | sed -n 's/^\[  FAILED  \] \([A-Za-z0-9_/]*\.[A-Za-z0-9_/]*\).*/\1/p' | sort -u | tr '\n' ' ')
            [ -n "$names" ] && failed="$failed$names"
            # A crash or an abort names no test: the binary's status says it failed.
            [ -z "$names" ] && [ $rc -ne 0 ] && failed="$failed$b(exit $rc) "
        done
    fi
    cp "$backup" "$file"; : >"$backup"; file=
    if [ -n "$failed" ]; then
        killed=$((killed + 1))
        printf '%-22s killed  %-45s by %s\n' "$id" "$stage" "$failed" | tee -a "$report"
    else
        survived=$((survived + 1))
        printf '%-22s SURVIVED %-44s (%s)\n' "$id" "$stage" "$binaries" | tee -a "$report"
    fi
done <"$list"
# The tree as it was: rebuild what the last mutant touched.
cmake --build "$build" >/dev/null 2>&1
echo "mutants: $killed killed, $survived survived, $broken broken (of $((killed + survived + broken)))"
[ "$survived" = 0 ] && [ "$broken" = 0 ]
