#!/usr/bin/env bash
# A real SLURM test of jobs/dipc_cpu.slurm (issue 13 part 6). Brings up a one-node SLURM from
# Debian's packages (munged, slurmctld, slurmd on 127.0.0.1, everything under a temporary
# directory), then:
#   1. runs the default scene on 2 ranks through the job script, uninterrupted (the reference);
#   2. submits the same job under another name and, once it has written a checkpoint,
#      requeues it with `scontrol requeue` (Slurm sends TERM to the job and SIGKILL KillWait
#      seconds later; the ranks checkpoint if they can in between; the job resumes from the
#      newest complete checkpoint);
#   3. once the resumed run has gone on, sends USR1 to the batch shell twice
#      (`scancel --signal=USR1 --batch`, what `--signal=B:USR1@margin` sends before a time
#      limit): the script forwards the first only, dipc writes a checkpoint and exits 4, the
#      script requeues the job, and the third run resumes from that checkpoint and finishes;
#   4. checks the log for each of these, and with tests/slurm/compare_outputs.py that every
#      written step of the interrupted job (HDF5, XDMF, stats.csv) equals the reference's;
#   5. runs jobs/dipc_gpu.slurm on this CPU node with the user's -dipc_backend cpu and an empty
#      DIPC_DEVICE_OPTS (the user's options win, the device options are cleared) and, where no
#      nvidia-smi is installed, once without GPUs (refused with a message, exit 1);
#   6. with DIPC_SLURM_TEST_TIME_LIMIT=1, runs a job into its time limit: Slurm's own
#      --signal=B:USR1 leads to checkpoint, exit 4, requeue and resume.
#
#   tests/slurm/run_slurm_requeue_test.sh build/src/app/dipc
#
# Needs root: installs slurm-wlm, munge, python3-h5py and python3-numpy with apt-get where
# missing (without starting Debian's services), and starts its own daemons, which it stops on
# exit. Exit status 0 passed, 1 failed, 77 cannot run here (not root, fewer than 2 CPUs).
# DIPC_SLURM_TEST_KEEP=1 keeps the temporary directory (logs, outputs) for inspection;
# DIPC_SLURM_TEST_TIME_LIMIT=1 adds phase 6 (1-2 minutes more).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
root=$(cd "$here/../.." && pwd)
script=$root/jobs/dipc_cpu.slurm
[[ $# -eq 1 ]] || { echo "usage: $0 <dipc program>" >&2; exit 2; }
dipc=$(realpath "$1")
[[ -x $dipc ]] || { echo "slurm test: no dipc program at $1" >&2; exit 1; }
steps=24           # of the default scene (40): about 0.1-1 s each on 2 ranks
every=2            # checkpoint every 2 steps
say() { echo "slurm test [$(date -u +%H:%M:%S)]: $*"; }

if [[ $(id -u) -ne 0 ]]; then
  say "SKIP: needs root (installs Debian packages, runs slurmd)"
  exit 77
fi
if (($(nproc) < 2)); then
  say "SKIP: needs 2 CPUs for a 2-rank job"
  exit 77
fi

# --- packages ------------------------------------------------------------------------------
packages=(slurm-wlm munge python3-h5py python3-numpy)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  say "installing ${missing[*]}"
  # Debian's postinst scripts would start the system's munge and slurm services; this test
  # runs its own, so service starts are refused while installing (policy-rc.d, exit 101).
  policy=/usr/sbin/policy-rc.d
  own_policy=0
  if [[ ! -e $policy ]]; then
    printf '#!/bin/sh\nexit 101\n' >"$policy"
    chmod 755 "$policy"
    own_policy=1
  fi
  apt-get update -q >/dev/null
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends "${missing[@]}" >/dev/null
  ((own_policy)) && rm -f "$policy"
fi

# --- a one-node cluster under a temporary directory ----------------------------------------
work=$(mktemp -d /tmp/dipc-slurm-test.XXXXXX)
chmod 755 "$work"   # munged wants its socket's directory searchable by all
mkdir -p "$work/state" "$work/spool" "$work/log" "$work/submit"
export SLURM_CONF=$work/slurm.conf
pids=()

dump_logs() {
  for f in "$work"/submit/*.out "$work"/log/*.log; do
    [[ -f $f ]] || continue
    echo "----- $f (last 60 lines)"
    tail -n 60 "$f"
  done
}
cleanup() {
  local status=$?
  trap - EXIT
  if [[ $status -ne 0 ]]; then dump_logs; fi
  if ((${#submitted[@]})); then
    scancel --quiet "${submitted[@]}" 2>/dev/null || true
    # Let the jobs' step daemons end before their slurmd does.
    for _ in $(seq 1 50); do
      [[ -z $(squeue -h 2>/dev/null) ]] && break
      sleep 0.2
    done
  fi
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do wait "$pid" 2>/dev/null || true; done
  if [[ -f $work/munged.pid ]]; then
    local munged_pid
    munged_pid=$(cat "$work/munged.pid")
    kill "$munged_pid" 2>/dev/null || true
    for _ in $(seq 1 50); do
      kill -0 "$munged_pid" 2>/dev/null || break
      sleep 0.1
    done
  fi
  if [[ ${DIPC_SLURM_TEST_KEEP:-0} == 1 ]]; then
    say "kept $work"
  else
    rm -rf "$work"
  fi
  exit "$status"
}
submitted=()
trap cleanup EXIT

mungekey -c -k "$work/munge.key" >/dev/null
munged --socket="$work/munge.socket" --key-file="$work/munge.key" --pid-file="$work/munged.pid" \
  --log-file="$work/log/munged.log" --seed-file="$work/munged.seed"

# Two free TCP ports for slurmctld and slurmd, so that a system's own SLURM is not disturbed.
read -r ctld_port slurmd_port < <(/usr/bin/python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*(x.getsockname()[1] for x in s))')

host=$(hostname -s)
# The node as slurmd sees it (CPUs, sockets, cores, threads, memory): slurmd refuses a node
# described with more than it has.
node=$(slurmd -C | head -n 1 | sed "s/^NodeName=[^ ]*/NodeName=$host NodeAddr=127.0.0.1/")
cat >"$SLURM_CONF" <<EOF
ClusterName=dipctest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
# A requeued job waits cred_expire seconds before it may start again (default 120).
AuthInfo=socket=$work/munge.socket,cred_expire=10
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
# Look at pending jobs every second (default 60), so that a requeued job starts promptly.
SchedulerParameters=sched_interval=1
MpiDefault=none
JobRequeue=1
ReturnToService=2
KillWait=10
$node State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

slurmctld -D -c >"$work/log/slurmctld.stdout" 2>&1 &
pids+=($!)
slurmd -D >"$work/log/slurmd.stdout" 2>&1 &
pids+=($!)
for i in $(seq 1 60); do
  [[ $(sinfo -h -o %T 2>/dev/null) == idle ]] && break
  ((i == 60)) && { say "FAIL: the node did not come up"; exit 1; }
  sleep 0.5
done
say "SLURM $(sinfo -V | cut -d' ' -f2) up: $node"

# --- helpers -------------------------------------------------------------------------------------
job_field() { scontrol show job -o "$1" | tr ' ' '\n' | sed -n "s/^$2=//p"; }
# Newest complete checkpoint step in a job's output directory (0 when none).
newest_checkpoint() {
  local newest=0 f k
  for f in "$work/submit/output/$1"/dipc.checkpoint.*.h5; do
    [[ -f $f ]] || continue
    k=${f##*checkpoint.}
    k=$((10#${k%.h5}))
    ((k > newest)) && newest=$k
  done
  echo "$newest"
}
# wait_for SECONDS DESCRIPTION COMMAND...: polls COMMAND until it succeeds.
wait_for() {
  local limit=$1 what=$2
  shift 2
  local end=$((SECONDS + limit))
  until "$@"; do
    if ((SECONDS > end)); then
      say "FAIL: waited $limit s for $what"
      exit 1
    fi
    sleep 0.2
  done
}
job_done() { [[ $(job_field "$1" JobState) =~ ^(COMPLETED|FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY)$ ]]; }
running_with_restarts() { [[ $(job_field "$1" JobState) == RUNNING && $(job_field "$1" Restarts) == "$2" ]]; }
# Like running_with_restarts, but a job that ended instead of being requeued fails at once.
running_again() {
  running_with_restarts "$1" "$2" && return 0
  if job_done "$1"; then
    say "FAIL: job $1 ended ($(job_field "$1" JobState), exit code $(job_field "$1" ExitCode)) instead of running again"
    exit 1
  fi
  return 1
}
checkpoint_at_least() { (($(newest_checkpoint "$1") >= $2)); }

# The job environment: the reference and the interrupted job alike. Open MPI polls while it
# waits unless it is told that cores may be shared; on a shared 2-core machine that makes
# srun-started ranks several times slower than under mpirun (which tells it).
export DIPC_BIN=$dipc OMPI_MCA_mpi_yield_when_idle=1
cd "$work/submit"
submit() { sbatch --parsable -J "$1" --ntasks=2 --time=15 "$script" -dipc_steps $steps -dipc_checkpoint_every $every; }

# --- 1. the uninterrupted reference ---------------------------------------------------------
t0=$SECONDS
ref=$(submit reference)
submitted+=("$ref")
wait_for 600 "the reference job $ref" job_done "$ref"
[[ $(job_field "$ref" JobState) == COMPLETED ]] || { say "FAIL: reference job $ref: $(job_field "$ref" JobState)"; exit 1; }
say "reference job $ref completed in $((SECONDS - t0)) s"

# --- 2. requeue mid-run ----------------------------------------------------------------------------
t0=$SECONDS
job=$(submit interrupted)
submitted+=("$job")
wait_for 300 "a checkpoint at step >= 2*$every of job $job" checkpoint_at_least interrupted $((2 * every))
running_with_restarts "$job" 0 || { say "FAIL: job $job is not in its first run"; exit 1; }
before_requeue=$(newest_checkpoint interrupted)
scontrol requeue "$job"
say "requeued job $job (newest checkpoint: step $before_requeue)"

# --- 3. USR1 to the batch shell of the second run ---------------------------------------------
wait_for 300 "job $job to run again" running_again "$job" 1
wait_for 300 "the resumed job $job to checkpoint beyond step $before_requeue" \
  checkpoint_at_least interrupted $((before_requeue + 2 * every))
before_signal=$(newest_checkpoint interrupted)
((before_signal < steps)) || { say "FAIL: the run ended before the signal; this machine is too fast for $steps steps"; exit 1; }
scancel --signal=USR1 --batch "$job"
# A second USR1 right behind it (as when the time limit's follows the user's own): the script
# must not pass it on, or dipc would exit at once without its checkpoint.
scancel --signal=USR1 --batch "$job"
say "sent USR1 twice to the batch shell of job $job (newest checkpoint: step $before_signal)"
wait_for 300 "job $job to run a third time" running_again "$job" 2
wait_for 600 "job $job to end" job_done "$job"
say "job $job ended: $(job_field "$job" JobState), exit code $(job_field "$job" ExitCode), restarts $(job_field "$job" Restarts), $((SECONDS - t0)) s"

# --- 4. checks -------------------------------------------------------------------------------------
log=$work/submit/dipc-interrupted-$job.out
failures=0
check() {  # check DESCRIPTION COMMAND...
  local what=$1
  shift
  if "$@"; then say "ok: $what"; else say "FAIL: $what"; failures=$((failures + 1)); fi
}
log_has() { grep -Eq "$1" "$log"; }
restart_steps=$(sed -n 's/^dipc: restarting from .*checkpoint\.0*\([0-9][0-9]*\)\.h5: step.*/\1/p' "$log" | tr '\n' ' ')
read -r first_restart second_restart rest <<<"$restart_steps "
check "the job completed after 2 requeues" \
  test "$(job_field "$job" JobState) $(job_field "$job" Restarts) $(job_field "$job" ExitCode)" == "COMPLETED 2 0:0"
check "run 1 started from step 0" log_has 'no checkpoint of "dipc" in .*, starting from step 0'
check "run 2 resumed from the newest checkpoint before the requeue (step ${first_restart:-none} >= $before_requeue)" \
  test "${first_restart:-0}" -ge "$before_requeue" -a "${first_restart:-0}" -gt 0
# Run 2's lines from the forwarded signal to the requeue.
signal_section=$(awk '/run 2 .*got USR1/ {on = 1} on {print} /run 2 .*requeueing the job/ {exit}' "$log")
section_has() { grep -Eq "$1" <<<"$signal_section"; }
check "run 2: the batch shell forwarded USR1" section_has 'got USR1: asking dipc'
check "run 2: the batch shell did not pass the second USR1 on" section_has 'got USR1 again: dipc is already stopping'
# srun reports the tasks' exit codes ("tasks 0-1: Exited with exit code 4", or one line per
# task): every rank must have ended with 4, none at once (128 + signal) on a second signal.
task_codes() { grep -o 'Exited with exit code [0-9]*' <<<"$signal_section" | awk '{print $5}' | sort -u | tr '\n' ' '; }
check "run 2: every rank exited with status 4 (codes seen: $(task_codes))" test "$(task_codes)" == "4 "
check "run 2: the script requeued the job" section_has 'checkpoint written; requeueing the job'
# dipc stops within the step that is running when the signal comes and keeps the last completed
# one: that may be the step of the newest periodic checkpoint (the signal came early in the next
# step), so run 3 must start from the step dipc names on stopping, which is not older than it.
signal_step=$(sed -n 's/^dipc: stopped on signal [0-9]* after step \([0-9]*\); checkpoint written.*/\1/p' <<<"$signal_section" | head -n 1)
check "run 3 resumed from the checkpoint written on the signal (step ${second_restart:-none}; dipc stopped after step ${signal_step:-none}, newest checkpoint before the signal $before_signal)" \
  test -n "$signal_step" -a "${second_restart:-0}" -eq "${signal_step:-0}" -a "${signal_step:-0}" -ge "$before_signal"
check "run 3 finished" log_has 'run 3 .*finished'
check "the script never asked for a requeue that Slurm refused" bash -c "! grep -q 'requeue refused' '$log'"
check "the interrupted job's output equals the reference's at every step" \
  /usr/bin/python3 "$here/compare_outputs.py" "$work/submit/output/reference" "$work/submit/output/interrupted" --steps $steps

# The comparison can fail: the same check against an output with one written step removed.
cp -r "$work/submit/output/interrupted" "$work/lost_step"
/usr/bin/python3 -c "import h5py, sys; f = h5py.File(sys.argv[1], 'r+'); del f['steps/7']" "$work/lost_step/dipc.h5"
check "the comparison notices a lost step" bash -c "! /usr/bin/python3 '$here/compare_outputs.py' '$work/submit/output/reference' '$work/lost_step' >/dev/null"

# --- 5. the GPU script's options on this CPU node ----------------------------------------------
# With CUDA_VISIBLE_DEVICES passed in (as Slurm's gpu plugin sets it) the GPU script finds 2
# "GPUs" and binds one to each rank; the user's -dipc_backend cpu must win over its
# -dipc_backend cuda, and an empty DIPC_DEVICE_OPTS must drop -vec_type cuda -mat_type hypre
# (this CPU build and Debian's PETSc would refuse either). No GPU resource is requested, as on
# a site whose GPU resource has another name.
# DIPC_BIN is a probe that reports which GPUs each rank sees, then becomes dipc.
# shellcheck disable=SC2016 # the probe expands them
printf '#!/bin/bash\necho "rank $SLURM_PROCID (local $SLURM_LOCALID) sees CUDA_VISIBLE_DEVICES=${CUDA_VISIBLE_DEVICES-unset}"\nexec %q "$@"\n' \
  "$dipc" >"$work/gpu_probe"
chmod +x "$work/gpu_probe"
gpu_job=$(CUDA_VISIBLE_DEVICES=0,1 DIPC_DEVICE_OPTS='' DIPC_BIN=$work/gpu_probe sbatch --parsable -J gpu_script --ntasks-per-node=2 \
  --cpus-per-task=1 --time=5 "$root/jobs/dipc_gpu.slurm" -dipc_steps 3 -dipc_backend cpu)
submitted+=("$gpu_job")
wait_for 300 "the GPU script's job $gpu_job" job_done "$gpu_job"
gpu_log=$work/submit/dipc-gpu_script-$gpu_job.out
check "GPU script: completed with the user's -dipc_backend cpu and no device options" \
  test "$(job_field "$gpu_job" JobState)" == COMPLETED
check "GPU script: 2 GPUs found, bound by local rank, no -vec_type" \
  bash -c "grep -q '2 GPU(s) per node, binding local_rank' '$gpu_log' && ! grep -q -- '-vec_type' '$gpu_log'"
check "GPU script: the user's backend won" grep -q 'backend cpu (requested)' "$gpu_log"
check "GPU script: rank 0 sees GPU 0 only, rank 1 GPU 1 only" bash -c \
  "grep -q 'rank 0 (local 0) sees CUDA_VISIBLE_DEVICES=0\$' '$gpu_log' && grep -q 'rank 1 (local 1) sees CUDA_VISIBLE_DEVICES=1\$' '$gpu_log'"
if ! command -v nvidia-smi >/dev/null; then
  nogpu_job=$(env -u CUDA_VISIBLE_DEVICES sbatch --parsable -J no_gpu --ntasks-per-node=2 --cpus-per-task=1 \
    --time=5 "$root/jobs/dipc_gpu.slurm" -dipc_steps 3)
  submitted+=("$nogpu_job")
  wait_for 120 "the GPU script's job $nogpu_job" job_done "$nogpu_job"
  check "GPU script without GPUs: exit 1 and a message naming the sbatch options" bash -c \
    "[[ '$(job_field "$nogpu_job" ExitCode)' == 1:0 ]] && grep -q 'no GPU in this job: submit with --gpus-per-node' '$work/submit/dipc-no_gpu-$nogpu_job.out'"
fi

# --- 6. optional: the time-limit signal itself ----------------------------------------------------
# DIPC_SLURM_TEST_TIME_LIMIT=1: a job with --time=2 and --signal=B:USR1@45 (in place of the
# script's 300 s margin) must get USR1 from Slurm before its time limit, write a checkpoint,
# exit 4, requeue itself and resume from that checkpoint. slurmctld looks at time limits every
# 30 s and sends the signal once margin + 30 s are left: here 45-75 s after the start (with
# --time=1 it came at once, before dipc had its handler: status 138). Off by default: it takes
# 1-2 minutes however fast the machine is.
if [[ ${DIPC_SLURM_TEST_TIME_LIMIT:-0} == 1 ]]; then
  limit_job=$(sbatch --parsable -J time_limit --ntasks=2 --time=2 --signal=B:USR1@45 "$script" \
    -dipc_steps 100000 -dipc_checkpoint_every 1000)
  submitted+=("$limit_job")
  limit_log=$work/submit/dipc-time_limit-$limit_job.out
  wait_for 300 "job $limit_job to be requeued at its time limit and run again" running_again "$limit_job" 1
  wait_for 120 "the requeued job $limit_job to resume" grep -q '^dipc: restarting from' "$limit_log"
  scancel "$limit_job"
  limit_section=$(awk '/run 1 .*got USR1/ {on = 1} on {print} /run 1 .*requeueing the job/ {exit}' "$limit_log")
  stopped_at=$(sed -n 's/^dipc: stopped on signal 10 after step \([0-9]*\);.*/\1/p' <<<"$limit_section")
  resumed_at=$(sed -n 's/^dipc: restarting from .*: step \([0-9]*\),.*/\1/p' "$limit_log" | head -n 1)
  check "time limit: Slurm's USR1 reached the batch shell, dipc stopped after step ${stopped_at:-none}, the script requeued the job" \
    bash -c "[[ -n '$stopped_at' ]] && grep -q 'requeueing the job' <<<'$limit_section'"
  check "time limit: run 2 resumed from that step (${resumed_at:-none})" test "${resumed_at:-x}" == "${stopped_at:-y}"
  echo "----- job log $limit_log (without the step lines)"
  grep -v '^step ' "$limit_log"
fi

echo "----- job log $log"
cat "$log"
echo "----- job log $gpu_log"
cat "$gpu_log"
if ((failures)); then
  say "FAILED: $failures check(s)"
  exit 1
fi
say "PASSED"
