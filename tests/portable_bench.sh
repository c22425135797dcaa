#!/usr/bin/env bash
# The portable bench archive (tools/pack-bench.sh, docs/performance.md "A portable bench"),
# outside the default suite: it builds a second tree and packs ~190 MB of libraries.
#
#   tests/portable_bench.sh [ARCHIVE]   default: pack one with tools/pack-bench.sh
#
# Checks that the archive is at most 50 MB, then unpacks it into a temporary folder and
# runs its launcher under `env -i` (no PATH, no LD_LIBRARY_PATH, nothing of this shell's)
# on fill_flat at 1 and 2 threads, which must print a ratio at each count and resolve every
# library but glibc from the bundle. As root, it also runs it chrooted into a root that
# holds only glibc (libc, libm, the loader) and /bin/sh beside the unpacked archive: the
# nearest this machine has to a bare one, so a library or file found only because this
# machine has it installed fails here.
set -euo pipefail
cd "$(dirname "$0")/.."
say() { printf 'portable_bench: %s\n' "$*" >&2; }
fail() { say "FAIL: $*"; exit 1; }

archive="${1:-}"
if [ -z "$archive" ]; then
    archive=$(tools/pack-bench.sh)
fi
size=$(stat -c %s "$archive")
[ "$size" -le $((50 * 1000 * 1000)) ] || fail "$archive is $size bytes, over 50 MB"
say "$archive: $size bytes"

scratch=$(mktemp -d "${TMPDIR:-/tmp}/portable_bench.XXXXXX")
trap 'rm -rf "$scratch"' EXIT
tar -C "$scratch" -xJf "$archive"
pkg="$scratch/retroglass-bench"

# Every library resolves from the bundle, but glibc's.
while read -r soname arrow path _; do
    [ "$arrow" = "=>" ] || continue
    case "$soname" in libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|libmvec.so.*) continue ;; esac
    case "$path" in "$pkg/lib/"*) ;; *) fail "$soname resolves to $path, outside the bundle" ;; esac
done < <(env -i LD_LIBRARY_PATH="$pkg/lib" ldd "$pkg/bin/retroglass")

# The run's output must give fill_flat a ratio at 1 and at 2 threads.
check_run() {
    local what="$1" out="$2"
    printf '%s\n' "$out" | grep -Eq '^fill_flat vs llvmpipe +[0-9]+\.[0-9]{2} +[0-9]+\.[0-9]{2}$' ||
        fail "$what: no ratio at 1 and 2 threads in:
$out"
    say "$what: ok"
    printf '%s\n' "$out" | grep -E 'at threads:|^fill_flat vs' >&2
}
args=(bench --threads 1,2 --filter '^fill_flat/' --min-time 0.02)
out=$(cd "$scratch" && env -i ./retroglass-bench/retroglass "${args[@]}" 2>&1) ||
    fail "env -i run exited with $?:
$out"
check_run "env -i" "$out"

if [ "$(id -u)" = 0 ] && command -v chroot >/dev/null 2>&1; then
    root="$scratch/root"
    mkdir -p "$root/lib/x86_64-linux-gnu" "$root/lib64" "$root/bin" "$root/tmp"
    cp -L /lib/x86_64-linux-gnu/libc.so.6 /lib/x86_64-linux-gnu/libm.so.6 "$root/lib/x86_64-linux-gnu/"
    cp -L /lib64/ld-linux-x86-64.so.2 "$root/lib64/"
    cp -L /bin/sh "$root/bin/sh"
    mv "$pkg" "$root/"
    out=$(env -i "$(command -v chroot)" "$root" /retroglass-bench/retroglass "${args[@]}" 2>&1) ||
        fail "chrooted run exited with $?:
$out"
    check_run "chroot with glibc alone" "$out"
else
    say "not root or no chroot: the glibc-only root is not tried"
fi
