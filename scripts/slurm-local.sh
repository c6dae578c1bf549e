#!/usr/bin/env bash
# A real single-node Slurm cluster on this machine, for tests of `sdv sweep --slurm` (issue 16):
# Debian's slurm-wlm and munge, the daemons (munged, slurmctld, slurmd) started by hand (no
# systemd), every socket bound to 127.0.0.1, and all state (slurm.conf, munge key and socket,
# spool, logs, pid files) under one STATE_DIR. Nothing is written to /etc or /run.
#
#   eval "$(scripts/slurm-local.sh up [STATE_DIR])"   # prints `export SLURM_CONF=STATE_DIR/slurm.conf`
#   ... sbatch / squeue / sdv sweep --slurm ...        # SLURM_CONF must be set for every command
#   scripts/slurm-local.sh down STATE_DIR
#
# `up` creates STATE_DIR (default: a fresh `mktemp -d`; its name is printed on stderr), writes
# slurm.conf with the machine's real CPUs and memory (`slurmd -C`) and two free TCP ports, starts
# the daemons and polls `sinfo` (at most 150 times, 0.1 s apart) until the node is idle; if it
# never is, it prints the daemons' logs, stops what it started and exits 1. Its only stdout line
# is the export line. The first job is started about 3 s after `up` (slurmctld's first
# scheduling pass), later ones within a second.
#
# `down STATE_DIR` cancels the jobs left, sends SIGTERM to the daemons whose pids `up` recorded
# (STATE_DIR/<daemon>.pid: used only while that pid is still the daemon of this STATE_DIR),
# waits for them (about 2 s), then stops whatever else the cluster left: a daemon that ignored
# SIGTERM, slurmstepd processes (found by SLURM_CONF=STATE_DIR/slurm.conf in their environment)
# and their job processes, with SIGTERM then SIGKILL. It exits 1, naming them, if any survives.
# STATE_DIR stays (logs) for the caller to remove. Several clusters can run at once (each has its
# own ports, munge socket and state); `up` refuses a STATE_DIR whose cluster is still running.
#
# Throughput: Slurm 22.05 starts jobs only on slurmctld's once-a-second scheduling pass, so with
# one job per CPU a 2-CPU machine runs 2 array tasks a second however short they are. The
# partition therefore oversubscribes the CPUs to SLURM_LOCAL_SLOTS jobs in all (default 256;
# OverSubscribe=FORCE:<slots/CPUs>; cons_tres still counts each job's --cpus-per-task), so that
# short tasks are bound by the launch cost instead (~45 ms of CPU per task on a 2-core VM:
# 1,000 trivial tasks in about 20 s). Far more slots is slower (slurmd runs out of threads and
# RPCs time out). SLURM_LOCAL_SLOTS=<number of CPUs> gives one job per CPU.
#
# Root vs not root: CI runs this as root: SlurmUser=root and jobs run as root. As an ordinary
# user (tried on Debian 12 with Slurm 22.05.8) everything runs as that user, SlurmUser included,
# and that user's jobs run (slurmctld logs "Not running as root. Can't drop supplementary
# groups"); jobs of any other user cannot run, since slurmd cannot switch users without root.
#
# Requires: slurm-wlm (slurmctld, slurmd, sinfo, squeue, scancel) and munge (munged, mungekey).
set -euo pipefail

die() { echo "slurm-local.sh: $*" >&2; exit 1; }

usage() {
    echo "usage: slurm-local.sh up [STATE_DIR] | down STATE_DIR" >&2
    exit 2
}

# Daemons in start order; each writes STATE_DIR/<name>.pid.
daemons=(munged slurmctld slurmd)

# The ports listening on this machine (hex from /proc/net/tcp{,6}, state 0A = LISTEN), decimal.
listening_ports() {
    cat /proc/net/tcp /proc/net/tcp6 2>/dev/null |
        awk 'NR > 1 && $4 == "0A" { split($2, a, ":"); print a[2] }' |
        while read -r hex; do echo $((16#$hex)); done | sort -un
}

# Two consecutive free ports in 20000..39999 (slurmctld, then slurmd).
free_port_pair() {
    local used base
    used=" $(listening_ports | tr '\n' ' ') "
    for _ in $(seq 1 200); do
        base=$((20000 + (RANDOM * 32768 + RANDOM) % 19999))
        if [[ $used != *" $base "* && $used != *" $((base + 1)) "* ]]; then
            echo "$base"
            return 0
        fi
    done
    die "no free TCP port pair found"
}

pid_alive() { [ -n "$1" ] && kill -0 "$1" 2>/dev/null; }

# daemon_pid STATE NAME: the pid in STATE/NAME.pid if that process is still NAME and its command
# line names STATE (a stale pid file may hold a pid reused by an unrelated process); else nothing.
daemon_pid() {
    local state=$1 name=$2 pid comm words=()
    [ -s "$state/$name.pid" ] || return 0
    read -r pid <"$state/$name.pid" || true
    [[ $pid =~ ^[0-9]+$ ]] || return 0
    { read -r comm <"/proc/$pid/comm"; } 2>/dev/null || return 0
    [ "$comm" = "$name" ] || return 0
    { mapfile -d '' -t words <"/proc/$pid/cmdline"; } 2>/dev/null || return 0
    [[ " ${words[*]} " == *"$state/"* ]] && echo "$pid"
    return 0
}

print_logs() {
    local state=$1 f
    for f in "$state"/log/*; do
        [ -s "$f" ] || continue
        echo "----- $f (last 40 lines) -----" >&2
        tail -n 40 "$f" >&2
    done
}

# The live processes of the cluster in STATE, one "pid name" a line: its daemons (any munged,
# slurmctld or slurmd whose command line names STATE), the slurmstepd processes its slurmd
# started (reparented to init, but with SLURM_CONF=STATE/slurm.conf in their environment), and
# every descendant of those (slurmscriptd, job processes). The /proc walk uses bash builtins only
# (a fork per process is slow on these machines).
cluster_processes() {
    local state=$1 d p comm pp w
    local -A parent=() ours=()
    local words=()
    for d in /proc/[0-9]*; do
        p=${d#/proc/}
        { read -r comm <"$d/comm"; } 2>/dev/null || continue
        # The parent is the 2nd field after "(comm) ", comm may hold blanks.
        { read -r pp <"$d/stat"; } 2>/dev/null || continue
        pp=${pp##*) }
        read -r _ pp _ <<<"$pp"
        parent[$p]=$pp
        case $comm in
            munged | slurmctld | slurmd)
                { mapfile -d '' -t words <"$d/cmdline"; } 2>/dev/null || continue
                [[ " ${words[*]} " == *"$state/"* ]] && ours[$p]=$comm ;;
            slurmstepd)
                { mapfile -d '' -t words <"$d/environ"; } 2>/dev/null || continue
                for w in "${words[@]}"; do
                    if [ "$w" = "SLURM_CONF=$state/slurm.conf" ]; then
                        ours[$p]=$comm
                        break
                    fi
                done ;;
        esac
    done
    local grown=1
    while [ $grown = 1 ]; do
        grown=0
        for p in "${!parent[@]}"; do
            if [ -z "${ours[$p]:-}" ] && [ -n "${ours[${parent[$p]}]:-}" ]; then
                { read -r comm <"/proc/$p/comm"; } 2>/dev/null || comm=process
                ours[$p]=$comm
                grown=1
            fi
        done
    done
    for p in "${!ours[@]}"; do
        if [ "$p" != "$$" ] && pid_alive "$p"; then echo "$p ${ours[$p]}"; fi
    done
    return 0
}

# signal_and_wait SIGNAL POLLS PID...: send SIGNAL, then wait (at most POLLS x 0.1 s) for all.
signal_and_wait() {
    local sig=$1 polls=$2 p left
    shift 2
    for p in "$@"; do kill "-$sig" "$p" 2>/dev/null || true; done
    for _ in $(seq 1 "$polls"); do
        left=0
        for p in "$@"; do pid_alive "$p" && left=1; done
        [ $left = 0 ] && return 0
        sleep 0.1
    done
    return 0
}

# Stops the cluster in STATE and whatever it left running; returns 1 if a process survives.
stop_cluster() {
    local state=$1 name pid jobs left
    local -a pids=()
    # Running jobs would leave slurmstepd processes behind: cancel them while slurmctld can.
    if [ -n "$(daemon_pid "$state" slurmctld)" ] && [ -f "$state/slurm.conf" ]; then
        jobs=$(SLURM_CONF="$state/slurm.conf" timeout 10 squeue -h -o %A 2>/dev/null | sort -u | tr '\n' ' ' || true)
        if [ -n "${jobs// /}" ]; then
            # shellcheck disable=SC2086
            SLURM_CONF="$state/slurm.conf" timeout 10 scancel $jobs 2>/dev/null || true
            for _ in $(seq 1 50); do
                [ -z "$(SLURM_CONF="$state/slurm.conf" timeout 10 squeue -h -o %A 2>/dev/null || true)" ] && break
                sleep 0.1
            done
        fi
    fi
    # The daemons: SIGTERM to all at once (each takes 1-2 s; none needs another to shut down).
    for name in "${daemons[@]}"; do
        pid=$(daemon_pid "$state" "$name")
        [ -n "$pid" ] && pids+=("$pid")
    done
    if [ ${#pids[@]} -gt 0 ]; then signal_and_wait TERM 100 "${pids[@]}"; fi
    # What is left: a daemon that ignored SIGTERM, slurmstepd processes and their jobs.
    left=$(cluster_processes "$state")
    if [ -n "$left" ]; then
        echo "slurm-local.sh: stopping what is left: $(tr '\n' ' ' <<<"$left")" >&2
        # shellcheck disable=SC2046
        signal_and_wait TERM 20 $(cut -d' ' -f1 <<<"$left")
        left=$(cluster_processes "$state")
    fi
    if [ -n "$left" ]; then
        # shellcheck disable=SC2046
        signal_and_wait KILL 20 $(cut -d' ' -f1 <<<"$left")
        left=$(cluster_processes "$state")
    fi
    if [ -n "$left" ]; then
        echo "slurm-local.sh: still running after SIGKILL: $(tr '\n' ' ' <<<"$left")" >&2
        return 1
    fi
    return 0
}

# fail_up STATE MESSAGE: print the logs, stop what was started, exit 1.
fail_up() {
    print_logs "$1"
    stop_cluster "$1" || true
    die "$2"
}

# wait_for_pid STATE NAME: the daemon has written its pid file and is alive (bounded).
wait_for_pid() {
    local state=$1 name=$2
    for _ in $(seq 1 100); do
        [ -n "$(daemon_pid "$state" "$name")" ] && return 0
        sleep 0.05
    done
    fail_up "$state" "$name did not start (no live $name pid in $state/$name.pid)"
}

cmd_up() {
    local state=${1:-} tool
    export PATH="$PATH:/usr/sbin:/sbin"
    for tool in munged mungekey slurmctld slurmd sinfo squeue scancel; do
        command -v "$tool" >/dev/null 2>&1 ||
            die "$tool not found: install slurm-wlm and munge (scripts/install-deps.sh --tests)"
    done
    if [ -z "$state" ]; then
        state=$(mktemp -d /tmp/slurm-local.XXXXXX)
    else
        mkdir -p "$state"
    fi
    state=$(cd "$state" && pwd -P)
    local running
    running=$(cluster_processes "$state")
    [ -z "$running" ] ||
        die "a cluster is still running in $state ($(tr '\n' ' ' <<<"$running")): run 'slurm-local.sh down $state' first"
    echo "slurm-local.sh: state in $state" >&2
    # munged refuses key and socket directories writable by group or others, and warns when
    # the socket's directories are not searchable by all (the key itself is 0600).
    chmod 755 "$state"
    rm -f "$state"/*.pid
    mkdir -p "$state/log" "$state/munge" "$state/ctld" "$state/spool"
    chmod 755 "$state/munge"

    local host user node port slots ncpu per_cpu oversub
    host=$(hostname -s 2>/dev/null || hostname)
    user=$(id -un)
    # "NodeName=vm CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24105"
    node=$(slurmd -C 2>/dev/null | head -n 1 | sed -E 's/^NodeName=[^ ]+ //') || die "slurmd -C failed"
    [[ $node =~ CPUs=([0-9]+) ]] || die "unexpected output of slurmd -C: $node"
    ncpu=${BASH_REMATCH[1]}
    port=$(free_port_pair)
    slots=${SLURM_LOCAL_SLOTS:-256}
    [[ $slots =~ ^[0-9]+$ && $slots -ge 1 ]] || die "SLURM_LOCAL_SLOTS must be a positive integer, not '$slots'"
    per_cpu=$(((slots + ncpu - 1) / ncpu))
    if [ "$per_cpu" -le 1 ]; then oversub=OverSubscribe=NO; else oversub=OverSubscribe=FORCE:$per_cpu; fi

    cat >"$state/slurm.conf" <<EOF
# Written by scripts/slurm-local.sh up: a single-node test cluster bound to 127.0.0.1.
ClusterName=sdvlocal
SlurmctldHost=$host(127.0.0.1)
CommunicationParameters=NoCtldInAddrAny,NoInAddrAny
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$state/munge/munge.socket
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/log/slurmctld.log
SlurmdLogFile=$state/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig=$state/plugstack.conf
MailProg=/bin/true
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
ReturnToService=2
MaxArraySize=100001
MaxJobCount=200000
MinJobAge=10
KillWait=5
InactiveLimit=0
SlurmctldTimeout=30
SlurmdTimeout=30
# Jobs start on the once-a-second scheduling pass: no extra delay for batch jobs, and the whole
# queue (every task of a large array) considered in each pass.
SchedulerType=sched/builtin
SchedulerParameters=default_queue_depth=10000,batch_sched_delay=0
NodeName=$host NodeAddr=127.0.0.1 NodeHostname=$host $node State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP $oversub
EOF
    : >"$state/plugstack.conf"

    # munge: its own key, socket, pid, log and seed files. --force: start even when a socket
    # was left behind by a killed munged.
    mungekey --create --keyfile="$state/munge/munge.key" --force >/dev/null 2>&1 ||
        die "mungekey could not create $state/munge/munge.key"
    chmod 600 "$state/munge/munge.key"
    export SLURM_CONF="$state/slurm.conf"   # the daemons' children (slurmstepd) carry it

    munged --force --socket="$state/munge/munge.socket" --key-file="$state/munge/munge.key" \
        --pid-file="$state/munged.pid" --log-file="$state/log/munged.log" \
        --seed-file="$state/munge/munged.seed" </dev/null >>"$state/log/munged.out" 2>&1 ||
        fail_up "$state" "munged failed to start"
    wait_for_pid "$state" munged
    slurmctld -f "$state/slurm.conf" </dev/null >>"$state/log/slurmctld.out" 2>&1 ||
        fail_up "$state" "slurmctld failed to start"
    wait_for_pid "$state" slurmctld
    slurmd -f "$state/slurm.conf" -N "$host" </dev/null >>"$state/log/slurmd.out" 2>&1 ||
        fail_up "$state" "slurmd failed to start"
    wait_for_pid "$state" slurmd

    local st=""
    for _ in $(seq 1 150); do
        st=$(timeout 5 sinfo -h -n "$host" -o %t 2>/dev/null || true)
        [ "$st" = idle ] && break
        sleep 0.1
    done
    [ "$st" = idle ] || fail_up "$state" "node $host not idle after 150 polls of sinfo (state: '${st:-none}')"
    echo "export SLURM_CONF=$state/slurm.conf"
}

cmd_down() {
    local state=$1
    [ -d "$state" ] || die "no state directory $state"
    state=$(cd "$state" && pwd -P)
    stop_cluster "$state"
}

case "${1:-}" in
    up) shift; [ $# -le 1 ] || usage; cmd_up "${1:-}" ;;
    down) shift; [ $# -eq 1 ] || usage; cmd_down "$1" ;;
    *) usage ;;
esac
