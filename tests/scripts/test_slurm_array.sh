#!/usr/bin/env bash
# The Slurm array end to end (issue 23, docs/distributed.md): starts a private single-node Slurm
# cluster on this machine (munged, slurmctld and slurmd from a generated slurm.conf with
# proctrack/linuxproc and no cgroups, on their own ports and state directories), submits
# scripts/slurm/submit.sh for a small media scene (train + 4 chunks + merge), waits with a timeout,
# compares the merged image with the single-process render of the same samples, requeues a chunk of a
# second submission and checks it resumed from its checkpoint, then has Slurm send SIGTERM to a long chunk and checks the partial image it wrote, and stops the daemons it
# started (by their pids). Exit 77 (CTest: skipped) where Slurm cannot run: not root, or
# slurm-wlm / munge not installed (`make deps` installs them).
#   tests/scripts/test_slurm_array.sh VOLGUIDE_CLI REPO_DIR
set -euo pipefail
cli=$(realpath "$1")
repo=$(realpath "$2")
skip() { echo "SKIPPED: $*"; exit 77; }
[[ $(id -u) -eq 0 ]] || skip "the Slurm test needs root (it starts munged, slurmctld and slurmd)"
for tool in munged slurmctld slurmd sbatch scontrol sinfo; do
    command -v "$tool" >/dev/null || skip "$tool is not installed (make deps installs slurm-wlm and munge)"
done

work=$(mktemp -d /tmp/volguide-slurm.XXXXXX)
chmod 755 "$work"
pids=()
cleanup() {
    local status=$?
    for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
    for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
    if [[ $status -ne 0 ]]; then
        echo "--- logs in $work (kept) ---"
        tail -n 20 "$work"/*.log "$work"/out/logs/* 2>/dev/null || true
    else
        rm -rf "$work"
    fi
}
trap cleanup EXIT

# munge: a private key, socket and logs.
mkdir -p "$work/munge"
chmod 711 "$work/munge"
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --foreground --force --socket "$work/munge/munge.sock" --key-file "$work/munge/munge.key" \
    --pid-file "$work/munge/munged.pid" --log-file "$work/munged.log" --seed-file "$work/munge/seed" \
    >"$work/munged.stdout.log" 2>&1 &
pids+=($!)

host=$(hostname -s)
port=$(( 20000 + RANDOM % 20000 ))
mkdir -p "$work/state" "$work/spool" "$work/out"
cat > "$work/slurm.conf" <<CONF
ClusterName=volguidetest
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/slurmctld.log
SlurmdLogFile=$work/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$work/slurm.conf
sleep 1
slurmctld -D -f "$SLURM_CONF" >"$work/slurmctld.stdout.log" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" >"$work/slurmd.stdout.log" 2>&1 &
pids+=($!)

for _ in $(seq 60); do
    sinfo -h -o %t 2>/dev/null | grep -q idle && break
    sleep 1
done
sinfo -h -o %t | grep -q idle || { echo "the Slurm node never became idle"; exit 1; }

# guided_volpath with its defaults (the allocation learned in the training file's pre-pass), fewer photons.
cat > "$work/fog.xml" <<'XML'
<scene version="3.0.0">
    <integrator type="guided_volpath">
        <integer name="photons" value="20000"/>
    </integrator>
    <medium type="homogeneous" id="fog">
        <rgb name="sigma_t" value="0.6, 0.3, 0.9"/>
        <rgb name="albedo" value="0.9"/>
        <phase type="hg"><float name="g" value="0.6"/></phase>
    </medium>
    <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/></shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/><translate y="-1.01"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5"/></bsdf>
    </shape>
    <emitter type="point"><point name="position" value="1.6, 0.3, 0"/><rgb name="intensity" value="8"/></emitter>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="-0.5, 0.8, 4" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="24"/>
            <rfilter type="gaussian"/></film>
    </sensor>
</scene>
XML

ids=$(VOLGUIDE="$cli" "$repo/scripts/slurm/submit.sh" "$work/fog.xml" "$work/out" 4 3 11 -- --cpus-per-task=1)
read -r train array merge <<<"$ids"
echo "submitted: train $train, array $array, merge $merge"
state=""
for _ in $(seq 300); do
    state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 || true)
    [[ "$state" == COMPLETED || "$state" == FAILED || "$state" == CANCELLED ]] && break
    sleep 1
done
[[ "$state" == COMPLETED ]] || { echo "merge job ended as '${state:-unknown}' (timeout 300 s)"; exit 1; }

cat "$work"/out/logs/merge-*.out
grep -q "samples: 0:12" "$work"/out/logs/merge-*.out
# The single process renders from the same training file: a render without one learns its allocation
# from its own passes, which chunks of samples cannot share (docs/distributed.md).
"$cli" render "$work/fog.xml" --field "$work/out/field.vgt" --seed 11 --spp 12 -o "$work/single.exr" --quiet
"$cli" diff "$work/out/merged.exr" "$work/single.exr" --json > "$work/diff.json"
python3 - "$work/diff.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print("merged vs single process: relMSE(1e-2) =", d["relmse_1e-2"], " mean ratio =", d["ratio"])
assert d["relmse_1e-2"] < 1e-12, d
PY
echo "PASSED: the Slurm array (train + 4 chunks + merge) equals the single-process render"

# Requeue (issue 61): chunk 0 of a second submission is requeued (scontrol requeue, what preemption
# with PreemptMode=REQUEUE does) once its checkpoint exists; it runs again, resumes from the
# checkpoint (chunk.sbatch), and writes the uninterrupted chunk byte for byte; the merge equals the
# single-process render.
rq_spp=${VOLGUIDE_TEST_REQUEUE_SPP:-400}
mkdir -p "$work/rq"
ids=$(VOLGUIDE="$cli" VOLGUIDE_CHECKPOINT_EVERY=0.2 VOLGUIDE_ARGS="--threads 1" \
    "$repo/scripts/slurm/submit.sh" "$work/fog.xml" "$work/rq" 2 "$rq_spp" 11 -- --cpus-per-task=1)
read -r train array merge <<<"$ids"
echo "submitted: train $train, array $array, merge $merge (chunk 0 to be requeued)"
for _ in $(seq 600); do
    [[ -f "$work/rq/chunk-0.ckpt" ]] && break
    sleep 0.2
done
[[ -f "$work/rq/chunk-0.ckpt" ]] || { echo "chunk 0 wrote no checkpoint"; exit 1; }
scontrol requeue "${array}_0"
state=""
for _ in $(seq 400); do
    state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | cut -d= -f2 || true)
    [[ "$state" == COMPLETED || "$state" == FAILED || "$state" == CANCELLED ]] && break
    sleep 1
done
[[ "$state" == COMPLETED ]] || { echo "the requeue's merge job ended as '${state:-unknown}' (timeout 400 s)"; exit 1; }
chunk_log=$(ls "$work"/rq/logs/chunk-*_0.out)
cat "$chunk_log"
grep -q "^interrupted" "$chunk_log" || { echo "chunk 0 was not interrupted by the requeue (make it longer)"; exit 1; }
grep -q "resuming from" "$chunk_log" || { echo "the requeued chunk 0 did not resume from its checkpoint"; exit 1; }
"$cli" render "$work/fog.xml" --field "$work/rq/field.vgt" --seed 11 --samples "0:$rq_spp" -o "$work/rq/single-0.exr" --quiet
cmp "$work/rq/chunk-0.exr" "$work/rq/single-0.exr" || { echo "the resumed chunk differs from the uninterrupted one"; exit 1; }
"$cli" render "$work/fog.xml" --field "$work/rq/field.vgt" --seed 11 --spp $((2 * rq_spp)) -o "$work/rq/single.exr" --quiet
"$cli" diff "$work/rq/merged.exr" "$work/rq/single.exr" --json > "$work/rq/diff.json"
python3 - "$work/rq/diff.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print("requeued array merged vs single process: relMSE(1e-2) =", d["relmse_1e-2"])
assert d["relmse_1e-2"] < 1e-12, d
PY
echo "PASSED: a requeued chunk resumed from its checkpoint (bit for bit) and the merge equals the single process"

# Preemption: a chunk of a million samples per pixel gets SIGTERM from Slurm (scancel --batch:
# the batch process, which chunk.sbatch exec'd into volguide) and writes the passes it completed.
mkdir -p "$work/pre/logs"
cp "$work/out/field.vgt" "$work/pre/field.vgt"
job=$(VOLGUIDE="$cli" VOLGUIDE_SCENE="$work/fog.xml" VOLGUIDE_OUT="$work/pre" VOLGUIDE_SPP=1000000 \
    VOLGUIDE_SEED=11 VOLGUIDE_ARGS="--threads 1" sbatch --parsable --export=ALL --array=0 \
    --chdir "$work/pre" -o "$work/pre/logs/chunk-%A_%a.out" "$repo/scripts/slurm/chunk.sbatch")
for _ in $(seq 60); do
    squeue -h -j "$job" -o %T 2>/dev/null | grep -q RUNNING && break
    sleep 1
done
sleep 3
scancel --batch --signal=TERM "$job"
for _ in $(seq 120); do
    [[ -z "$(squeue -h -j "$job" 2>/dev/null)" ]] && break
    sleep 1
done
cat "$work"/pre/logs/chunk-*.out
[[ -f "$work/pre/chunk-0.exr" ]] || { echo "the preempted chunk wrote nothing"; exit 1; }
"$cli" merge "$work/pre/chunk-0.exr" -o "$work/pre/merged.exr" | tee "$work/pre/merge.txt"
count=$(sed -n 's/^samples: 0:\([0-9]*\)$/\1/p' "$work/pre/merge.txt")
[[ -n "$count" && "$count" -ge 1 && "$count" -lt 1000000 ]] || { echo "unexpected range in the partial chunk"; exit 1; }
# From the same training file: the single process renders the partial chunk's samples.
"$cli" render "$work/fog.xml" --field "$work/pre/field.vgt" --seed 11 --spp "$count" -o "$work/pre/single.exr" --quiet
"$cli" diff "$work/pre/merged.exr" "$work/pre/single.exr" --json > "$work/pre/diff.json"
python3 - "$work/pre/diff.json" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
print("preempted chunk vs single process: relMSE(1e-2) =", d["relmse_1e-2"])
assert d["relmse_1e-2"] < 1e-12, d
PY
echo "PASSED: a chunk preempted by Slurm (SIGTERM) wrote its completed passes, 0:$count"
