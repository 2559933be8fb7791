#!/usr/bin/env bash
# A real single-node Slurm on localhost (Debian's slurm-wlm and munge), a 4-task job array of
# `gimg batch` shards, the merge, and the check that it equals one process's run. Environment: GIMG
# (the binary), WORK (a scratch folder of its own), COLLECTION (a folder of meshes). Exit 77 (skip)
# when Slurm or munge is not installed. Everything it starts is stopped at the end.
set -uo pipefail
for tool in slurmctld slurmd munged sbatch squeue; do
  command -v "$tool" >/dev/null || { echo "skipped: $tool is not installed (./run bench installs slurm-wlm and munge)"; exit 77; }
done
[ -d "$COLLECTION" ] || { echo "skipped: no collection at $COLLECTION (../shared/meshes)"; exit 77; }
W="$WORK/slurm"
rm -rf "$W" && mkdir -p "$W"/{munge,state,spool,logs} || exit 1
host=$(hostname -s)
pids=()
stop() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null; done
  for f in "$W/slurmctld.pid" "$W/slurmd.pid"; do [ -f "$f" ] && kill "$(cat "$f")" 2>/dev/null; done
  [ -f "$W/munge/munged.pid" ] && kill "$(cat "$W/munge/munged.pid")" 2>/dev/null
  sleep 0.5
}
trap stop EXIT
fail() { echo "FAIL: $*"; for f in "$W"/logs/*.log; do echo "--- $f"; tail -20 "$f"; done; exit 1; }

dd if=/dev/urandom of="$W/munge/munge.key" bs=1024 count=1 status=none && chmod 400 "$W/munge/munge.key"
munged --force --key-file="$W/munge/munge.key" --socket="$W/munge/munge.socket" \
  --pid-file="$W/munge/munged.pid" --log-file="$W/logs/munged.log" --seed-file="$W/munge/seed" ||
  fail "munged did not start"

# Ports from the process id, so two runs on one machine do not collide.
port=$((20000 + ($$ % 20000)))
cat >"$W/slurm.conf" <<CONF
ClusterName=gimgtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$W/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$W/state
SlurmdSpoolDir=$W/spool
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/logs/slurmctld.log
SlurmdLogFile=$W/logs/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
NodeName=$host NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=gimg Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$W/slurm.conf"
slurmctld -i || fail "slurmctld did not start"
slurmd || fail "slurmd did not start"
for _ in $(seq 100); do sinfo -h -o %t 2>/dev/null | grep -Eq '^(idle|mix)' && break; sleep 0.2; done
sinfo -h -o %t | grep -Eq '^(idle|mix)' || fail "the node did not come up: $(sinfo 2>&1)"

# The 4-task array of shards, then the merge, against one process over the whole collection.
sbatch --wait --array=0-3 --output="$W/logs/task-%a.log" --job-name=gimg-shards \
  --wrap "'$GIMG' batch info --inputs '$COLLECTION' --out '$W/shards' --shard \$SLURM_ARRAY_TASK_ID/4 --quiet" \
  >"$W/logs/sbatch.log" 2>&1 || fail "the array failed: $(cat "$W/logs/sbatch.log")"
"$GIMG" batch merge "$W/shards" --out "$W/merged.jsonl" || fail "merge failed"
"$GIMG" batch info --inputs "$COLLECTION" --out "$W/one" --quiet || fail "the single run failed"
strip() { sed -E 's/"seconds":[^,}]*//g' "$1" | sort; }
[ "$(strip "$W/merged.jsonl")" = "$(strip "$W/one/results.jsonl")" ] || fail "the array's merged results differ from one run"
models=$(wc -l <"$W/merged.jsonl")
echo "ok: 4 Slurm tasks ($(ls "$W/shards"/results-*-of-4.jsonl | wc -l) shard files) merged into $models models, equal to one run"
