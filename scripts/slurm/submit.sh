#!/usr/bin/env bash
# Renders one image on a Slurm cluster (docs/distributed.md): one training job, an array of chunk
# jobs that depends on it (chunk i renders samples [i*SPP, (i+1)*SPP) of every pixel with the
# trained field), and a merge job that runs after the whole array, whatever became of its tasks
# (a preempted chunk is requeued and resumes from its checkpoint, chunk.sbatch; a chunk that still
# ended early writes the passes it completed, and merge reports what is missing).
#
#   scripts/slurm/submit.sh SCENE.xml OUTDIR CHUNKS SPP_PER_CHUNK [SEED] [-- sbatch options...]
#
# OUTDIR must be on a filesystem every node sees. Environment: VOLGUIDE (the CLI, default: volguide on
# PATH), VOLGUIDE_ARGS (more render/train options, e.g. "-D res=4"), VOLGUIDE_TRAIN_TIME (train --time),
# VOLGUIDE_SIGNAL_LEAD (seconds before a chunk's time limit that it gets SIGTERM, default 300; "" = none),
# VOLGUIDE_CHECKPOINT_EVERY (seconds between a chunk's checkpoints, default 60).
# Prints the three job ids (train, array, merge) on one line.
set -euo pipefail

if [[ $# -lt 4 ]]; then
    sed -n '2,14p' "$0" >&2
    exit 2
fi
scene=$(realpath "$1")
outdir=$(realpath -m "$2")
chunks=$3
spp=$4
shift 4
seed=0
if [[ $# -gt 0 && "$1" != "--" ]]; then
    seed=$1
    shift
fi
if [[ $# -gt 0 && "$1" == "--" ]]; then shift; fi
here=$(dirname "$(realpath "$0")")
mkdir -p "$outdir/logs"

export VOLGUIDE_SCENE=$scene VOLGUIDE_OUT=$outdir VOLGUIDE_SPP=$spp VOLGUIDE_SEED=$seed VOLGUIDE_CHUNKS=$chunks
export VOLGUIDE=${VOLGUIDE:-$(command -v volguide || echo volguide)}
export VOLGUIDE_ARGS=${VOLGUIDE_ARGS:-} VOLGUIDE_TRAIN_TIME=${VOLGUIDE_TRAIN_TIME:-}
export VOLGUIDE_CHECKPOINT_EVERY=${VOLGUIDE_CHECKPOINT_EVERY:-60}

common=(--parsable --export=ALL --chdir "$outdir" "$@")
train=$(sbatch "${common[@]}" --job-name vg-train -o "$outdir/logs/train-%j.out" "$here/train.sbatch")
lead=${VOLGUIDE_SIGNAL_LEAD-300}
signal=()
[[ -n "$lead" ]] && signal=(--signal "B:TERM@$lead")
# --requeue (also in chunk.sbatch): a preempted chunk runs again from its checkpoint.
array=$(sbatch "${common[@]}" "${signal[@]}" --requeue --job-name vg-chunk --dependency "afterok:$train" --array "0-$((chunks - 1))" \
    -o "$outdir/logs/chunk-%A_%a.out" "$here/chunk.sbatch")
merge=$(sbatch "${common[@]}" --job-name vg-merge --dependency "afterany:$array" \
    -o "$outdir/logs/merge-%j.out" "$here/merge.sbatch")
echo "$train $array $merge"
