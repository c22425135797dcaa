#!/bin/sh
# `retroglass bench --trace` on one golden trace (docs/testing.md): the replay must be timed
# on ours and, unless Mesa lacks a feature the trace uses, on llvmpipe, at 1 and 2 threads,
# with a ratio per thread count; a trace Mesa cannot play must get its "ours only" line.
#   bench_trace_check.sh RETROGLASS TRACE both|ours-only
set -u
retroglass=$1 trace=$2 expect=$3
name=$(basename "$trace" .trace)
out=$("$retroglass" --threads 2 bench --trace "$trace" --min-time 0.01 2>&1)
rc=$?
printf '%s\n' "$out"
fail() {
    echo "FAIL: $*"
    echo "reproduce: $retroglass --threads 2 bench --trace $trace --min-time 0.01"
    exit 1
}
[ $rc -eq 0 ] || fail "exit status $rc"
printf '%s\n' "$out" | grep -q "ERROR OCCURRED" && fail "a benchmark reported an error"
for t in 1 2; do
    printf '%s\n' "$out" | grep -q "trace:$name/retroglass/threads:$t/manual_time" ||
        fail "ours was not timed at $t threads"
    ratio="^trace:$name/retroglass/threads:$t/manual_time vs llvmpipe +[0-9.e+]+ +[0-9.e+]+ +[0-9]+\.[0-9]+\$"
    if [ "$expect" = both ]; then
        printf '%s\n' "$out" | grep -q "trace:$name/llvmpipe/threads:$t/manual_time" ||
            fail "llvmpipe was not timed at $t threads"
        printf '%s\n' "$out" | grep -Eq "$ratio" || fail "no ratio line at $t threads"
    else
        printf '%s\n' "$out" | grep -q "trace:$name/llvmpipe" && fail "llvmpipe was run on a trace it cannot play"
    fi
done
if [ "$expect" = ours-only ]; then
    printf '%s\n' "$out" | grep -Eq "^trace:$name +ours only: Mesa lacks " || fail "no 'ours only' line"
fi
echo "ok"
