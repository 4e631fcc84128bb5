#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for running the study Makefiles' CLUSTER=slurm switch
# (pipelines/cluster.mk) without a real cluster: the end-to-end test's, or by hand.
#   scripts/local-slurm.sh start  [DIR] [--owner PID]
#                                         install (as root, if missing), configure, start, wait idle;
#                                         with --owner, stop it when process PID ends (a test that
#                                         dies or times out leaves no daemons behind)
#   scripts/local-slurm.sh status [DIR]   the node's state, or "not running"
#   scripts/local-slurm.sh stop   [DIR]   cancel its jobs, stop its daemons
# DIR (default ${TMPDIR:-/tmp}/shapepress-slurm) holds everything: slurm.conf, a munge key and
# socket of its own, state, spool, logs and pid files; the ports are two free ones picked at start.
# So it runs beside a system Slurm or munge, or another DIR's cluster, without touching them.
# `start` prints the line SLURM_CONF=DIR/slurm.conf: srun/sinfo/squeue need it in the environment.
# Exit codes of start: 0 running; 77 Slurm cannot be had here (not root, or the Debian packages
# missing and not installable), which a test reports as a skip; 1 it should have started and did
# not (the logs are printed).
set -euo pipefail

action="${1:-}"
dir="${TMPDIR:-/tmp}/shapepress-slurm"
owner=""
shift || true
while [[ $# -gt 0 ]]; do
  case "$1" in
    --owner)
      owner="${2:?--owner needs a process id}"
      shift 2
      ;;
    *)
      dir="$1"
      shift
      ;;
  esac
done
packages=(slurmctld slurmd slurm-client munge)

usage() {
  echo "usage: $0 start|stop|status [DIR] [--owner PID]" >&2
  exit 2
}

# A process that runs (an exited daemon may stay a zombie a while where nobody reaps it).
# (/proc rather than ps: a minimal Debian has no procps.)
alive() {
  local stat
  stat=$(cat "/proc/$1/stat" 2>/dev/null) || return 1
  [[ "${stat##*) }" != Z* ]]
}

# The pid in a pid file, if that process is alive.
live_pid() {
  local pid
  [[ -f "$1" ]] || return 1
  pid=$(cat "$1" 2>/dev/null) || return 1
  [[ -n "$pid" ]] && alive "$pid" && echo "$pid"
}

stop_daemon() {
  local pid
  pid=$(live_pid "$1") || return 0
  kill "$pid" 2>/dev/null || true
  for _ in $(seq 50); do
    alive "$pid" || return 0
    sleep 0.1
  done
  kill -9 "$pid" 2>/dev/null || true
}

stop_cluster() {
  if live_pid "$dir/slurmctld.pid" >/dev/null && [[ -f "$dir/slurm.conf" ]]; then
    SLURM_CONF="$dir/slurm.conf" scancel --quiet --full --state=RUNNING,PENDING \
      --user="$(id -un)" 2>/dev/null || true
  fi
  stop_daemon "$dir/slurmd.pid"
  stop_daemon "$dir/slurmctld.pid"
  stop_daemon "$dir/munge/munged.pid"
}

have_packages() {
  local p status
  for p in "${packages[@]}"; do
    status=$(dpkg-query -W -f='${db:Status-Status}' "$p" 2>/dev/null || true)
    [[ "$status" == "installed" ]] || return 1
  done
}

# A TCP port nobody listens on, from a range away from Slurm's defaults (6817/6818).
free_port() {
  local port
  for _ in $(seq 100); do
    port=$((20000 + RANDOM % 20000))
    [[ " $* " == *" $port "* ]] && continue
    # Nobody answers a connection there (bash's /dev/tcp: a minimal Debian has no ss).
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
      echo "$port"
      return 0
    fi
  done
  return 1
}

# A watcher in its own session: stops the cluster once the owner process is gone, and ends by
# itself when the cluster is stopped.
watch_owner() {
  setsid "$(realpath "$0")" watch "$dir" --owner "$owner" </dev/null >/dev/null 2>&1 &
}

watch() {
  while alive "$owner" && live_pid "$dir/slurmctld.pid" >/dev/null; do sleep 1; done
  alive "$owner" || stop_cluster
}

fail() {
  echo "local-slurm.sh: $1" >&2
  for log in "$dir/munge/munged.log" "$dir/slurmctld.log" "$dir/slurmd.log"; do
    [[ -f "$log" ]] && { echo "--- $log (last lines)" >&2; tail -n 20 "$log" >&2; }
  done
  stop_cluster
  exit 1
}

start() {
  if [[ $(id -u) -ne 0 ]]; then
    echo "local-slurm.sh: slurmd runs jobs as their user, so a local cluster needs root" >&2
    exit 77
  fi
  if ! have_packages; then
    echo "local-slurm.sh: installing ${packages[*]}" >&2
    # The packages' own services stay as the machine's init decides; this cluster uses none of
    # their files (/etc/slurm, /etc/munge, /run/munge).
    if ! { DEBIAN_FRONTEND=noninteractive apt-get update -qq &&
      DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        "${packages[@]}" >/dev/null; }; then
      echo "local-slurm.sh: could not install ${packages[*]}" >&2
      exit 77
    fi
  fi
  if live_pid "$dir/slurmctld.pid" >/dev/null; then
    echo "local-slurm.sh: already running in $dir (stop it first)" >&2
    exit 1
  fi
  stop_cluster # whatever a crashed start left behind in this folder
  rm -rf "$dir/state" "$dir/spool" "$dir/munge" "$dir"/*.log "$dir/slurm.conf"
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 0700 "$dir/munge"
  dir=$(cd "$dir" && pwd)
  # A Unix socket's path holds at most 107 bytes.
  [[ ${#dir} -le 80 ]] || fail "$dir is too long a path for munge's socket (at most 80 characters)"

  # munge: its own key and socket; slurm.conf's AuthInfo points the daemons and clients at it.
  mungekey --create --keyfile="$dir/munge/munge.key" >/dev/null
  chmod 0400 "$dir/munge/munge.key"
  # --force: the folder may sit under a world-writable /tmp, which munged otherwise refuses.
  munged --force --socket="$dir/munge/munge.socket" --key-file="$dir/munge/munge.key" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munged.seed" 2>>"$dir/munge/munged.log" ||
    fail "munged did not start"

  local node ctld_port slurmd_port
  # slurmd -C: this machine's node line (its host name, CPUs, sockets, cores, memory in MB).
  node=$(slurmd -C | head -n 1)
  [[ "$node" == NodeName=* ]] || fail "slurmd -C gave no node line: $node"
  local name=${node%% *}
  name=${name#NodeName=}
  ctld_port=$(free_port) || fail "no free port for slurmctld"
  slurmd_port=$(free_port "$ctld_port") || fail "no free port for slurmd"
  cat >"$dir/slurm.conf" <<EOF
# Written by scripts/local-slurm.sh: a one-node cluster in $dir.
ClusterName=shapepress
SlurmctldHost=$name(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
# No cgroups: processes tracked by their parent, no binding; the jobs see the whole machine.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
SchedulerType=sched/backfill
# CPUs are the consumable: jobs share the node, each holding its --cpus-per-task.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MailProg=/bin/true
# Finished jobs stay listed (scontrol show jobs) for an hour, not 5 minutes: what a test checks.
MinJobAge=3600
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=local Nodes=$name Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
  slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
  for _ in $(seq 300); do
    if [[ $(sinfo -h -N -o %t 2>/dev/null) == idle ]]; then
      [[ -n "$owner" ]] && watch_owner
      echo "SLURM_CONF=$SLURM_CONF"
      return 0
    fi
    sleep 0.1
  done
  fail "the node did not come up idle within 30 s: $(sinfo -N 2>&1 || true)"
}

status() {
  if ! live_pid "$dir/slurmctld.pid" >/dev/null; then
    echo "not running ($dir)"
    return 3
  fi
  SLURM_CONF="$dir/slurm.conf" sinfo -N
}

case "$action" in
  start) start ;;
  stop) stop_cluster ;;
  status) status ;;
  watch) watch ;;
  *) usage ;;
esac
