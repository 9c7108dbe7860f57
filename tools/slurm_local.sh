#!/usr/bin/env bash
# tools/slurm_local.sh — a real single-node Slurm cluster (slurmctld + slurmd +
# a private munged) for kiln farm tests and for trying `kiln farm` locally.
#
#   tools/slurm_local.sh start    install packages if needed, start, wait for idle node
#   tools/slurm_local.sh stop     cancel jobs, stop daemons, remove all state
#   tools/slurm_local.sh status   sinfo + squeue (exit 1 if not running)
#   tools/slurm_local.sh env      print `export SLURM_CONF=...`
#
#   eval "$(tools/slurm_local.sh start)"   # start and point clients at it
#
# Everything (config, munge key/socket, state, spool, logs, pids) lives under
# $KILN_SLURM_DIR, so /etc/slurm and any system munged are never touched.
# See docs/farm-local-cluster.md: job states come from squeue/scontrol and
# `sacct -c` (job-completion log); plain `sacct` needs slurmdbd and is off.
set -euo pipefail

DIR=$(realpath -m "${KILN_SLURM_DIR:-/tmp/kiln-slurm}")
CTLD_PORT=${KILN_SLURM_CTLD_PORT:-16817}
SLURMD_PORT=${KILN_SLURM_SLURMD_PORT:-16818}
CLUSTER=${KILN_SLURM_CLUSTER:-kiln}
PARTITION=${KILN_SLURM_PARTITION:-kiln}
# A requeued job may not start again for cred_expire seconds (Slurm default
# 120); a short value keeps requeue tests fast. Credentials never travel far.
CRED_EXPIRE=${KILN_SLURM_CRED_EXPIRE:-10}
# Seconds between SIGTERM and SIGKILL on scancel / time limit (default 30).
KILL_WAIT=${KILN_SLURM_KILL_WAIT:-5}
START_TIMEOUT=${KILN_SLURM_START_TIMEOUT:-30}

CONF=$DIR/slurm.conf
MARKER=$DIR/.kiln-slurm # only directories carrying this marker are rm -rf'd
MUNGE_SOCKET=$DIR/munge/munge.socket
DAEMONS=(munged slurmctld slurmd) # start order
# slurmctld/slurmd come from the packages of the same name; sbatch, squeue,
# sacct, scancel, scontrol and sinfo from slurm-client; munged from munge.
PACKAGES=(slurmctld slurmd slurm-client munge)

log() { echo "slurm_local: $*" >&2; }

# A failed start stops what it already launched but keeps $DIR/log to read.
CLEANUP_ON_DIE=0
die() {
    log "error: $*"
    [[ $CLEANUP_ON_DIE -eq 1 ]] && stop_daemons
    exit 1
}

run_root() {
    if [[ $EUID -eq 0 ]]; then "$@"; else sudo "$@"; fi
}

# --- packages ---------------------------------------------------------------

apt_install() {
    run_root env DEBIAN_FRONTEND=noninteractive \
        apt-get install -y --no-install-recommends "$@" >&2
}

ensure_packages() {
    local missing=() p
    for p in "${PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' ||
            missing+=("$p")
    done
    [[ ${#missing[@]} -eq 0 ]] && return 0
    log "installing ${missing[*]}"
    # In containers policy-rc.d keeps the packaged services from starting; on
    # a systemd host they may start with /etc/slurm config, which we ignore.
    apt_install "${missing[@]}" ||
        { run_root apt-get update >&2 && apt_install "${missing[@]}"; } ||
        die "could not install ${missing[*]}"
}

# --- process helpers --------------------------------------------------------

# True if pid $1 exists and is not a zombie (kill -0 succeeds on zombies).
alive() {
    local st
    st=$(ps -o stat= -p "$1" 2>/dev/null) && [[ $st != Z* ]]
}

# Prints the pid recorded for daemon $1 if it is alive and its command line
# mentions our DIR, so a recycled pid from a stale pid file is never killed.
daemon_pid() {
    local pidfile=$DIR/run/$1.pid pid
    [[ -s $pidfile ]] || return 1
    pid=$(<"$pidfile")
    [[ $pid =~ ^[0-9]+$ ]] && alive "$pid" || return 1
    { tr '\0' ' ' <"/proc/$pid/cmdline"; } 2>/dev/null | grep -qF -- "$DIR/" || return 1
    echo "$pid"
}

# True while the process launch() just started for daemon $1 lives. Unlike
# daemon_pid it skips the command-line check: between fork and exec (a loaded
# machine can stretch that) the child still shows bash's command line.
launched_alive() {
    local pidfile=$DIR/run/$1.pid
    [[ -s $pidfile ]] && alive "$(<"$pidfile")"
}

# Runs daemon $1 in the foreground flavour of its command line, in its own
# session (a harness killing its process group must not take the cluster
# down) and with stdio detached (so `eval "$(... start)"` returns).
# Our own pid file: it exists before the daemon can fail, which is what lets
# wait_for notice a daemon that died at once (e.g. port already in use). The
# daemons write theirs to NAME.own.pid: sharing one file, a daemon rewriting it
# (truncate, then write) left it empty for an instant, and a start-up check
# that read it then took a live munged for dead (a CI failure).
launch() {
    local name=$1
    shift
    setsid "$@" </dev/null >/dev/null 2>"$DIR/log/$name.stderr" &
    echo $! >"$DIR/run/$name.pid"
}

# TERM all given pids at once (each daemon takes ~2 s to exit), wait up to
# 5 s, then KILL whatever is left.
kill_pids() {
    local i pid left
    [[ $# -gt 0 ]] || return 0
    kill -TERM "$@" 2>/dev/null || true
    for ((i = 0; i < 50; i++)); do
        left=0
        for pid in "$@"; do alive "$pid" && left=1; done
        [[ $left -eq 1 ]] || return 0
        sleep 0.1
    done
    kill -KILL "$@" 2>/dev/null || true
}

# slurmstepd is double-forked away from slurmd but inherits its environment
# (SLURM_CONF=our conf), which is how we recognise this cluster's stepds.
our_stepds() {
    local p
    for p in $(pgrep -x slurmstepd || true); do
        { tr '\0' '\n' <"/proc/$p/environ"; } 2>/dev/null |
            grep -qxF "SLURM_CONF=$CONF" && echo "$p"
    done
    return 0
}

# Pid $1 and all its descendants (job processes left behind by a stepd).
process_tree() {
    local k
    echo "$1"
    for k in $(pgrep -P "$1" || true); do process_tree "$k"; done
}

# In the foreground each daemon copies its log to stderr, and only stderr has
# the errors printed before the log file is opened (e.g. a bad config line).
show_logs() {
    local f
    for f in "$DIR"/log/*.stderr; do
        [[ -s $f ]] || continue
        log "---- tail of $f"
        tail -n 15 "$f" >&2
    done
}

# --- configuration ----------------------------------------------------------

write_munge_key() {
    # 0755: clients of every user must reach the socket; the key is 0400.
    mkdir -m 0755 "$DIR/munge"
    mungekey --create --keyfile="$DIR/munge/munge.key" 2>/dev/null ||
        dd if=/dev/urandom of="$DIR/munge/munge.key" bs=1024 count=1 status=none
    chmod 0400 "$DIR/munge/munge.key"
}

# CPU count and memory as slurmd itself detects them (`slurmd -C`). Only
# CPUs= is configured, no sockets/cores/threads: Slurm then treats every
# hardware thread as a schedulable CPU, so N one-CPU tasks run side by side
# even on hyperthreaded hosts. RealMemory is trimmed by 5% so fluctuating
# container memory never drains the node ("Low RealMemory").
node_hw() {
    local line cpus mem
    line=$(slurmd -C 2>/dev/null | head -n1) || true
    cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$line")
    mem=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$line")
    [[ -n $cpus ]] || cpus=$(nproc)
    [[ -n $mem ]] || mem=$(awk '/^MemTotal:/ {print int($2 / 1024)}' /proc/meminfo)
    echo "CPUs=$cpus RealMemory=$((mem * 95 / 100))"
}

write_conf() {
    local host user hw
    host=$(hostname -s)
    user=$(id -un)
    hw=$(node_hw)
    : >"$DIR/plugstack.conf" # keep /etc/slurm/plugstack.conf out of this cluster
    cat >"$CONF" <<EOF
# Generated by tools/slurm_local.sh: single-node kiln test cluster.
ClusterName=$CLUSTER
# The name must equal \`hostname -s\` or slurmctld refuses to run; the address
# in parentheses means nothing depends on DNS.
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCKET,cred_expire=$CRED_EXPIRE

StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/run/slurmctld.own.pid
SlurmdPidFile=$DIR/run/slurmd.own.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
PlugStackConfig=$DIR/plugstack.conf
# Debian's default /usr/bin/mail is usually absent.
MailProg=/bin/true

# No cgroups anywhere: containers rarely offer a usable /sys/fs/cgroup.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
SwitchType=switch/none

# Per-CPU allocation so 1-CPU array tasks run side by side (CR_Core would give
# each task a whole core). Memory is not a consumable resource.
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
# Scheduling passes every 2 s instead of 60/30 s; no batching delay.
SchedulerParameters=sched_interval=2,bf_interval=2,batch_sched_delay=0,default_queue_depth=1000
# A job whose dependency can never be met (afterok on a failed or cancelled
# job) is cancelled instead of pending forever (DependencyNeverSatisfied).
DependencyParameters=kill_invalid_depend

JobRequeue=1
ReturnToService=2
# Trust the configured node size; never drain on hardware-detection mismatch.
SlurmdParameters=config_overrides
KillWait=$KILL_WAIT
# Finished jobs stay visible to squeue -t all / scontrol show job for a day.
MinJobAge=86400

# No slurmdbd (it needs MySQL/MariaDB), so plain sacct is unavailable.
# \`sacct -c\` and the key=value file below give final job states.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$DIR/log/jobcomp.txt

NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host $hw State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

# --- daemons ----------------------------------------------------------------

munge_ok() {
    munge -n --socket="$MUNGE_SOCKET" 2>/dev/null |
        unmunge --socket="$MUNGE_SOCKET" >/dev/null 2>&1
}
ctld_ok() { scontrol ping 2>/dev/null | grep -q 'is UP'; }
node_state() { sinfo -h -N -o '%t' 2>/dev/null; }
node_idle() { [[ $(node_state) == idle ]]; }
# A running cluster may have jobs on the node: any usable state will do.
node_up() { [[ $(node_state) =~ ^(idle|mix|alloc)$ ]]; }

# wait_for <daemon> <check...>: poll every 0.1 s up to START_TIMEOUT; give up
# at once if the daemon died (bad config, port in use) and show the logs.
wait_for() {
    local daemon=$1 i
    shift
    for ((i = 0; i < START_TIMEOUT * 10; i++)); do
        "$@" && return 0
        launched_alive "$daemon" || { show_logs; die "$daemon exited during start-up"; }
        sleep 0.1
    done
    show_logs
    die "timed out after ${START_TIMEOUT}s waiting for $daemon"
}

start_daemons() {
    # --force: munged refuses to run when any parent of KILN_SLURM_DIR is
    # group-writable (e.g. a 0775 home); the key itself stays private (0400).
    # --foreground logs to stderr only, i.e. $DIR/log/munged.stderr.
    launch munged munged --foreground --force --socket="$MUNGE_SOCKET" \
        --key-file="$DIR/munge/munge.key" --pid-file="$DIR/run/munged.own.pid" \
        --seed-file="$DIR/munge/munged.seed"
    wait_for munged munge_ok
    # -c: never recover jobs from an earlier cluster's state.
    launch slurmctld slurmctld -D -c -f "$CONF"
    wait_for slurmctld ctld_ok
    launch slurmd slurmd -D -f "$CONF" -N "$(hostname -s)"
    wait_for slurmd node_idle
}

all_running() {
    local d
    [[ -f $CONF ]] || return 1
    for d in "${DAEMONS[@]}"; do daemon_pid "$d" >/dev/null || return 1; done
    ctld_ok
}

# Cancel every job so no slurmstepd outlives the cluster, stop the daemons,
# then reap stepds and job processes that are still left.
stop_daemons() {
    local pids=() tree=() pid d i
    if daemon_pid slurmctld >/dev/null && ctld_ok; then
        scancel --partition="$PARTITION" 2>/dev/null || true
        for ((i = 0; i < (KILL_WAIT + 5) * 5; i++)); do
            [[ -z $(our_stepds) ]] && break
            sleep 0.2
        done
    fi
    for d in "${DAEMONS[@]}"; do
        pid=$(daemon_pid "$d") && pids+=("$pid")
    done
    kill_pids "${pids[@]}"
    for pid in $(our_stepds); do
        mapfile -t tree < <(process_tree "$pid")
        kill -KILL "${tree[@]}" 2>/dev/null || true
    done
}

remove_dir() {
    [[ -e $DIR ]] || return 0
    [[ $DIR != / && -d $DIR ]] || die "refusing to remove $DIR"
    if [[ -e $MARKER || -z $(ls -A "$DIR") ]]; then
        rm -rf "$DIR"
    else
        die "$DIR exists but was not made by this script; set KILN_SLURM_DIR"
    fi
}

# A listener already on our ports would make slurmctld exit (or, worse,
# make scontrol ping hang for MessageTimeout), so refuse up front.
check_ports() {
    local port
    for port in "$CTLD_PORT" "$SLURMD_PORT"; do
        if (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
            die "port $port is in use; set KILN_SLURM_CTLD_PORT / KILN_SLURM_SLURMD_PORT"
        fi
    done
}

# --- commands ---------------------------------------------------------------

print_env() { echo "export SLURM_CONF=$CONF"; }

cmd_start() {
    # As root the daemons run jobs for any user. Without root the cluster
    # still works, but only for the invoking user's jobs (slurmd cannot setuid).
    [[ $EUID -eq 0 ]] || log "warning: not root; only $(id -un)'s jobs can run"
    ensure_packages
    export SLURM_CONF=$CONF
    if all_running; then
        wait_for slurmd node_up
        print_env
        return 0
    fi
    # Anything else (stale dir, half-started cluster) is wiped and rebuilt.
    stop_daemons
    remove_dir
    check_ports
    CLEANUP_ON_DIE=1
    mkdir -p "$DIR"/{state,spool,run,log}
    chmod 0755 "$DIR"
    touch "$MARKER"
    write_munge_key
    write_conf
    start_daemons
    print_env
}

cmd_stop() {
    export SLURM_CONF=$CONF
    stop_daemons
    remove_dir
    log "stopped"
}

cmd_status() {
    export SLURM_CONF=$CONF
    if ! all_running; then
        log "not running (dir $DIR)"
        [[ -d $DIR ]] && show_logs
        return 1
    fi
    sinfo
    squeue
}

case ${1:-} in
start) cmd_start ;;
stop) cmd_stop ;;
status) cmd_status ;;
env) print_env ;;
*)
    echo "usage: $0 start|stop|status|env" >&2
    exit 2
    ;;
esac
