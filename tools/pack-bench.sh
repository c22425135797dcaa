#!/usr/bin/env bash
# The portable bench as one archive (docs/performance.md, "A portable bench"):
#
#   tools/pack-bench.sh [ARCHIVE]     default: build-portable/retroglass-bench.tar.xz
#
# Builds `retroglass` with -DRETROGLASS_PORTABLE_BENCH=ON in build-portable/ (its own
# build folder; RETROGLASS_PACK_BUILD_DIR to change it), then packs it with its
# shared-library closure as ldd resolves it here (Google Benchmark, TBB, libstdc++,
# OSMesa with llvmpipe, LLVM and what LLVM needs) into
#
#   retroglass-bench/retroglass        launcher: runs bin/retroglass on the bundled libs
#   retroglass-bench/bin/retroglass
#   retroglass-bench/lib/*.so*         named by soname, as the loader asks for them
#   retroglass-bench/README            what it is, how to run it, the glibc it needs
#
# glibc itself (libc, libm, libpthread, libdl, librt, ld-linux) is left out: it must be
# the target machine's own, which the other libraries' version needs are checked against.
# The archive must be at most 50 MB (issue 22); the script fails if it is larger.
# RETROGLASS_PACK_JOBS sets the build parallelism (default 2).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
build="${RETROGLASS_PACK_BUILD_DIR:-build-portable}"
archive="${1:-$build/retroglass-bench.tar.xz}"
case "$archive" in /*) ;; *) archive="$root/$archive" ;; esac
limit=$((50 * 1000 * 1000))
say() { printf 'pack-bench: %s\n' "$*" >&2; }

# ---- build ------------------------------------------------------------------------------
if [ ! -f "$build/CMakeCache.txt" ]; then
    gen=()
    command -v ninja >/dev/null 2>&1 && gen=(-G Ninja)
    say "configuring $build/ (Release, RETROGLASS_PORTABLE_BENCH=ON)"
    cmake -S . -B "$build" "${gen[@]}" -DCMAKE_BUILD_TYPE=Release -DRETROGLASS_PORTABLE_BENCH=ON >&2
fi
cmake --build "$build" --target retroglass -j "${RETROGLASS_PACK_JOBS:-2}" >&2
exe="$build/bin/retroglass"

# ---- the closure ------------------------------------------------------------------------
stage=$(mktemp -d "${TMPDIR:-/tmp}/pack-bench.XXXXXX")
trap 'rm -rf "$stage"' EXIT
pkg="$stage/retroglass-bench"
mkdir -p "$pkg/bin" "$pkg/lib"
cp "$exe" "$pkg/bin/retroglass"
# ldd lists every library the loader maps, transitively: "soname => path (address)".
# Copied under the soname (cp -L follows the soname symlink to the file).
is_glibc() {
    case "$1" in
        libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*|ld-linux*|libmvec.so.*) return 0 ;;
    esac
    return 1
}
missing=0
while read -r soname arrow path _; do
    [ "$arrow" = "=>" ] || continue
    is_glibc "$soname" && continue
    if [ ! -f "$path" ]; then
        say "ldd cannot resolve $soname"
        missing=1
        continue
    fi
    cp -L "$path" "$pkg/lib/$soname"
done < <(ldd "$exe")
[ "$missing" = 0 ] || exit 1

# The oldest glibc every packed file runs on: the highest GLIBC_x.y version any of them
# asks for (Debian 12's LLVM 15 and libstdc++ ask for 2.36's arc4random).
glibc=$(for f in "$pkg/bin/retroglass" "$pkg"/lib/*; do
            objdump -T "$f" | grep -o 'GLIBC_2\.[0-9]*' || true
        done | sort -t. -k2,2n -u | tail -1 | sed 's/GLIBC_//')

# ---- launcher and README ----------------------------------------------------------------
# POSIX sh with no external command (env -i leaves no PATH): the folder from $0.
cat > "$pkg/retroglass" <<'LAUNCHER'
#!/bin/sh
# The portable retroglass bench: bin/retroglass on the libraries in lib/ (see README).
case "$0" in */*) here="${0%/*}" ;; *) here=. ;; esac
LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export LD_LIBRARY_PATH
exec "$here/bin/retroglass" "$@"
LAUNCHER
chmod +x "$pkg/retroglass"
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
{
    echo "retroglass portable bench (commit $commit, built $(date -u +%Y-%m-%d))"
    echo
    echo "The pipeline, texture and programmable workloads of \`retroglass bench\`, ours"
    echo "against Mesa llvmpipe ($(basename "$(ls "$pkg"/lib/libOSMesa.so.* | head -1)"), bundled) in the same run."
    echo "Needs: x86-64 Linux with glibc >= $glibc; nothing else installed."
    echo
    echo "  ./retroglass bench --threads 1,2,4,8,16 --repetitions 3 --json r.json --plot r.svg"
    echo "  ./retroglass bench --help"
    echo
    echo "Bundled libraries: $(cd "$pkg/lib" && ls | tr '\n' ' ')"
} > "$pkg/README"

# ---- archive ----------------------------------------------------------------------------
mkdir -p "$(dirname "$archive")"
say "packing $(du -sh "$pkg" | cut -f1) into $archive"
XZ_OPT="-9 -T${RETROGLASS_PACK_JOBS:-2}" tar -C "$stage" -cJf "$archive" retroglass-bench
size=$(stat -c %s "$archive")
say "$archive: $size bytes ($(( (size + 500000) / 1000000 )) MB), glibc >= $glibc"
if [ "$size" -gt "$limit" ]; then
    say "larger than the 50 MB limit"
    exit 1
fi
echo "$archive"
