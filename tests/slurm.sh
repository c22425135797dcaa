#!/usr/bin/env bash
# The Slurm job array against the real scheduler (issue 21, item 4; docs/testing.md,
# "Slurm"): outside the default suite, as it installs packages and starts daemons.
#
#   tests/slurm.sh [BUILD_DIR]
#
# Installs Debian's slurm-wlm and munge (sudo apt-get when not root), starts munged, a
# single-node slurmctld and slurmd on localhost (own ports, config and state under
# BUILD_DIR/slurm-test, all stopped again at the end), submits tools/slurm/reproduce-array.sh
# for pem at quick quality as 3 array tasks over its 8 views, waits for the merge job, and
# checks that the merged reproduction equals a single-process run: every asset file byte for
# byte (timings aside: files.json, timing.json) and results.json without its timings.
# Exit 0 and "slurm: PASS" when all agree.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-$here/build}" && pwd)"
bin="$build/bin/retroglass"
[[ -x "$bin" ]] || { echo "slurm: build $bin first (ninja -C build retroglass)" >&2; exit 2; }
work="$build/slurm-test"
sudo=""
[[ $(id -u) -eq 0 ]] || sudo="sudo"

# ---- packages ------------------------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null || ! command -v jq >/dev/null; then
    $sudo apt-get update -qq
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends \
        slurm-wlm munge jq >/dev/null
fi

rm -rf "$work"
mkdir -p "$work"/{munge,state,spool,log,run}
pids=()
cleanup() {
    local status=$?
    for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
    for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
    if [[ $status -ne 0 ]]; then
        echo "slurm: FAIL (logs in $work/log)"
        tail -n 5 "$work"/log/*.log 2>/dev/null || true
    fi
}
trap cleanup EXIT

# ---- munge: its own key and socket ----------------------------------------------------------
mungekey --create --keyfile="$work/munge/munge.key" --force 2>/dev/null ||
    dd if=/dev/urandom of="$work/munge/munge.key" bs=1k count=1 status=none
chmod 0711 "$work/munge"  # munged wants its socket's folder searchable by all
chmod 0400 "$work/munge/munge.key"
socket="$work/munge/munge.socket"
munged --foreground --force --key-file="$work/munge/munge.key" --socket="$socket" \
    --pid-file="$work/run/munged.pid" --log-file="$work/log/munged.log" \
    --seed-file="$work/munge/seed" 2>>"$work/log/munged.out" &
pids+=($!)
for _ in $(seq 50); do [[ -S "$socket" ]] && break; sleep 0.2; done
[[ -S "$socket" ]] || { echo "slurm: munged did not start" >&2; exit 1; }

# ---- a one-node cluster on localhost ----------------------------------------------------------
node=$(cat /proc/sys/kernel/hostname)
cpus=$(nproc)
cat > "$work/slurm.conf" <<EOF
ClusterName=retroglass-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/run/slurmctld.pid
SlurmdPidFile=$work/run/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
SlurmctldTimeout=30
SlurmdTimeout=30
InactiveLimit=0
MinJobAge=300
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$work/slurm.conf"
slurmctld -D -i -f "$SLURM_CONF" >>"$work/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" >>"$work/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 60); do
    sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed)' && break
    sleep 1
done
sinfo
sinfo -h -o '%T' | grep -qE '^(idle|mixed)' || { echo "slurm: the node did not come up" >&2; exit 1; }

# ---- the array and its merge ---------------------------------------------------------------
start=$(date +%s)
ids=$(RETROGLASS="$bin" "$here/tools/slurm/reproduce-array.sh" pem quick 8 3 "$work/cluster" \
          --cpus-per-task=1)
echo "$ids"
merge=$(awk '/^merge/ {print $2}' <<<"$ids")
# The single-process run, meanwhile, for the comparison.
"$bin" --threads 1 reproduce pem --quality quick --out "$work/single" >"$work/log/single.log" 2>&1 &
single=$!
while squeue -h -j "$merge" 2>/dev/null | grep -q .; do
    squeue -h -o '%.12i %.16j %.8T %.10M' || true
    sleep 15
done
wait "$single" || { echo "slurm: the single-process run failed" >&2; tail "$work/log/single.log"; exit 1; }
echo "slurm: array and merge done in $(( $(date +%s) - start )) s"
state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z]*' || true)
echo "slurm: merge job $merge $state"
for log in "$work/cluster/logs/views_"*.log; do
    echo "  $(basename "$log"): $(grep -h 'stored in' "$log" | sed 's/;.*//')"
done
grep -h '^merge:' "$work/cluster/logs/merge.log" | sed 's/^/  /'
tail -n 2 "$work/cluster/logs/merge.log" | sed 's/^/  /'
[[ -f "$work/cluster/merged/pem/results.json" ]] ||
    { echo "slurm: no merged results.json" >&2; cat "$work/cluster/logs/"*.log >&2; exit 1; }

# ---- byte for byte against the single process --------------------------------------------------
a="$work/single/pem/assets" b="$work/cluster/merged/pem/assets"
compared=0
while IFS= read -r f; do
    case "$(basename "$f")" in files.json|timing.json|shard.json) continue ;; esac
    cmp -s "$a/$f" "$b/$f" || { echo "slurm: assets/$f differs" >&2; exit 1; }
    compared=$((compared + 1))
done < <(cd "$a" && find . -type f | sort)
diff <(cd "$a" && find . -type f | sort) <(cd "$b" && find . -type f | sort) >/dev/null ||
    { echo "slurm: the merged assets hold other files than the single run's" >&2; exit 1; }
# shard.json: the same identity; only the ranges the runs recorded differ.
diff <(jq -S 'del(.ranges)' "$a/shard.json") <(jq -S 'del(.ranges)' "$b/shard.json")
echo "slurm: $compared asset files identical"
# The figures too: renders of the same maps, so the same pixels.
for f in "$work/single/pem/"*.png; do
    cmp -s "$f" "$work/cluster/merged/pem/$(basename "$f")" ||
        { echo "slurm: figure $(basename "$f") differs" >&2; exit 1; }
done
echo "slurm: $(ls "$work/single/pem/"*.png | wc -l) figures identical"
# results.json without what varies run to run: times, rates, the timed frames' counters.
strip='del(.. | objects | (.seconds_total, .raytrace_s_per_view, .inference_s_per_view, .inference_cpu_s_per_view,
                         .texgen_ms, .frame_ms, .fps, .test_renderings_s, .instrumented_s)?)'
diff <(jq -S "$strip" "$work/single/pem/results.json") \
     <(jq -S "$strip" "$work/cluster/merged/pem/results.json") ||
    { echo "slurm: results.json differs beyond timings" >&2; exit 1; }
echo "slurm: results.json identical (timings aside): $(jq -c '[.claims[]? | .holds] | {claims: length, hold: map(select(.)) | length}' "$work/cluster/merged/pem/results.json")"
echo "slurm: PASS"
