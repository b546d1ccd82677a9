#!/usr/bin/env bash
# scripts/slurm/ for real: a private Slurm cluster on this machine (munged, slurmctld and
# slurmd on 127.0.0.1 with their own key, socket, ports and spool in a temporary
# folder), a 4-slice array job of a scene plus the merge job, and a check that the merged
# folder equals a single-machine run byte for byte. Needs root (slurmd runs jobs as
# their user) and Debian's slurm-wlm + munge; exits 77 (skipped) without them.
#   tests/slurm_localhost.sh WAVE_EXE
set -euo pipefail
wave=$(realpath "$1")
repo=$(cd "$(dirname "$0")/.." && pwd)
for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
  command -v "$tool" >/dev/null || PATH=$PATH:/usr/sbin
  command -v "$tool" >/dev/null || { echo "skip: $tool not installed (Debian: slurm-wlm, munge)"; exit 77; }
done
if (($(id -u) != 0)); then echo "skip: slurmd must run as root to start jobs"; exit 77; fi

d=$(mktemp -d /tmp/libwave-slurm.XXXXXX)
chmod 755 "$d"
cleanup() {
  for p in slurmd slurmctld munged; do
    [[ -f $d/$p.pid ]] && kill "$(cat "$d/$p.pid")" 2>/dev/null || true
  done
  sleep 1
  rm -rf "$d"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*"
  for f in "$d"/slurmctld.log "$d"/slurmd.log "$d"/out.slurm-logs/*; do [[ -f $f ]] && { echo "== $f"; tail -20 "$f"; }; done
  exit 1
}

# A small scene: the default planar beach with one 5 s swell (20 frames at 4 fps).
scene=$d/beach.json
echo '{"name": "slurm-beach", "waves": [{"period": 5, "amplitude": 0.3}], "trace": {"ray_spacing": 2},
 "fronts": {"step": 0.8, "split_distance": 2.4}}' >"$scene"

# munge with its own key and socket (a system munged, if any, is left alone).
mkdir -p "$d/munge" && chmod 700 "$d/munge"
mungekey --create --keyfile="$d/munge/munge.key" --force
munged --force --socket="$d/munge/munge.socket" --key-file="$d/munge/munge.key" \
  --pid-file="$d/munged.pid" --log-file="$d/munged.log" --seed-file="$d/munge/seed"

# Ports from the pid: two test runs at once do not collide.
port=$((20000 + ($$ % 10000) * 2))
node=$(hostname -s)
mkdir -p "$d/state" "$d/spool"
cat >"$d/slurm.conf" <<CONF
ClusterName=libwave-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$d/munge/munge.socket
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$d/state
SlurmdSpoolDir=$d/spool
SlurmctldPidFile=$d/slurmctld.pid
SlurmdPidFile=$d/slurmd.pid
SlurmctldLogFile=$d/slurmctld.log
SlurmdLogFile=$d/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$d/slurm.conf
slurmctld -i
slurmd
for _ in $(seq 60); do
  sinfo -h -o %t 2>/dev/null | grep -qE '^(idle|mix|alloc)' && break
  sleep 1
done
sinfo -h -o %t | grep -qE '^(idle|mix|alloc)' || fail "the local node did not come up: $(sinfo 2>&1)"

# The array and the merge, then one run on this machine.
WAVE=$wave "$repo/scripts/slurm/submit.sh" --slices 4 --wait --sbatch "--time=10" "$scene" "$d/out" -- --fps 4 ||
  fail "the Slurm jobs failed"
for i in 0 1 2 3; do [[ -f $d/out.slurm-logs/slice-$i.out ]] || fail "slice $i left no log (did it run?)"; done
"$wave" run "$scene" -o "$d/whole" --form files --fps 4 -q
diff -r "$d/out" "$d/whole" || fail "the merged Slurm output differs from a single run"
frames=$(find "$d/out/frames" -name 'frame-*.glb' | wc -l)
((frames == 20)) || fail "expected the 20 frames of the loop, found $frames"

# A failing slice cancels the merge and the submission reports it.
if WAVE=$wave "$repo/scripts/slurm/submit.sh" --slices 4 --wait "$scene" "$d/bad" -- --fps 4 --threads -1 >/dev/null 2>&1; then
  fail "a failing array reported success"
fi
[[ ! -f $d/bad/index.json ]] || fail "the merge ran after failed slices"
echo "ok: 4 Slurm array tasks + merge = one run, byte for byte ($frames frames)"
