#!/usr/bin/env bash
# A paper's precompute as a Slurm job array, then one dependent job that merges the shards
# and evaluates (docs/cluster.md).
#
#   tools/slurm/reproduce-array.sh PAPER QUALITY VIEWS TASKS OUT [sbatch options...]
#
#   PAPER    pem (any paper whose precompute takes --views A:B)
#   QUALITY  quick | paper
#   VIEWS    the paper's viewpoint count at that quality (pem: quick 8, paper 100;
#            `retroglass reproduce --help` and the report's settings list it)
#   TASKS    array tasks; task i runs views [i·VIEWS/TASKS, (i+1)·VIEWS/TASKS)
#   OUT      a folder every node sees: OUT/shards/task_<i> per task, OUT/merged at the end
#   sbatch options go to every job (--partition=..., --time=..., --cpus-per-task=...).
#
# Environment: RETROGLASS, the built binary (default: build/bin/retroglass beside this
# script's checkout); it must be the same build on every node, as the merge refuses shards
# of another code version. Prints the two job ids: "array <id>" and "merge <id>".
set -euo pipefail

if [[ $# -lt 5 ]]; then
    sed -n '2,18p' "$0" >&2
    exit 2
fi
paper=$1 quality=$2 views=$3 tasks=$4 out=$5
shift 5
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"
bin="${RETROGLASS:-$here/build/bin/retroglass}"
[[ -x "$bin" ]] || { echo "reproduce-array: $bin is not an executable (set RETROGLASS)" >&2; exit 2; }
[[ "$views" =~ ^[0-9]+$ && "$tasks" =~ ^[0-9]+$ && $tasks -ge 1 && $views -ge $tasks ]] ||
    { echo "reproduce-array: need 1 ≤ TASKS ≤ VIEWS (got VIEWS=$views TASKS=$tasks)" >&2; exit 2; }
[[ ! -e "$out/merged/$paper" ]] ||
    { echo "reproduce-array: $out/merged/$paper exists; the merge would refuse it (choose another OUT)" >&2; exit 2; }
mkdir -p "$out/shards" "$out/logs"
out="$(cd "$out" && pwd)"

# ---- the array: one viewpoint range per task ----------------------------------------------
# A task that is requeued or rerun resumes its range: finished views are kept.
array=$(sbatch --parsable --job-name="rg-$paper-views" --array="0-$((tasks - 1))" \
    --output="$out/logs/views_%a.log" "$@" <<JOB
#!/usr/bin/env bash
set -euo pipefail
i=\$SLURM_ARRAY_TASK_ID
a=\$(( i * $views / $tasks )); b=\$(( (i + 1) * $views / $tasks ))
# As many threads as CPUs granted (all the node's without --cpus-per-task).
exec "$bin" \${SLURM_CPUS_PER_TASK:+--threads \$SLURM_CPUS_PER_TASK} reproduce "$paper" \
    --quality "$quality" --views "\$a:\$b" --out "$out/shards/task_\$i"
JOB
)
array=${array%%;*}

# ---- merge and evaluate, once every task succeeded -----------------------------------------
merge=$(sbatch --parsable --job-name="rg-$paper-merge" --dependency="afterok:$array" \
    --output="$out/logs/merge.log" "$@" <<JOB
#!/usr/bin/env bash
set -euo pipefail
"$bin" merge --out "$out/merged" "$out"/shards/task_*
exec "$bin" \${SLURM_CPUS_PER_TASK:+--threads \$SLURM_CPUS_PER_TASK} reproduce "$paper" \
    --quality "$quality" --out "$out/merged"
JOB
)
merge=${merge%%;*}
echo "array $array"
echo "merge $merge"
