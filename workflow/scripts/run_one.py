#!/usr/bin/env python3
"""Runs one glmbslam command for the workflow and records its provenance.

Usage: run_one.py --out DIR --provenance FILE --log FILE [--info JSON] -- COMMAND...

Runs COMMAND (a glmbslam invocation writing into DIR) with stdout and stderr to the log file, measures its wall
time and peak resident set size (getrusage of the child), and writes FILE (JSON): the command line, exit code,
wall time, peak RSS, git revision of the source tree (and whether it had uncommitted changes), the glmbslam
executable's path and modification time, machine (hostname, CPU model, cores), Slurm job id when run under
Slurm, start and end time (UTC), the SHA-256 of every config file named by --config, and the caller's --info
(dataset, algorithm, particles, seed, ...). Stale files from an earlier run in DIR are removed first, so the
folder only ever holds the outputs of this command. Exit code: the command's.
"""
import argparse
import datetime
import hashlib
import json
import os
import platform
import resource
import shutil
import socket
import subprocess
import sys
import time


def git_revision(root):
    def git(*args):
        try:
            return subprocess.run(["git", "-C", root, *args], capture_output=True, text=True,
                                  check=True).stdout.strip()
        except (OSError, subprocess.CalledProcessError):
            return None
    rev = git("rev-parse", "HEAD")
    status = git("status", "--porcelain", "--untracked-files=no")
    return rev, (None if status is None else bool(status))


def cpu_model():
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or None


def sha256(path):
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 16), b""):
            h.update(chunk)
    return h.hexdigest()


def main():
    if "--" not in sys.argv:
        sys.exit("run_one.py: missing '--' before the command")
    split = sys.argv.index("--")
    parser = argparse.ArgumentParser()
    parser.add_argument("--out", required=True)
    parser.add_argument("--provenance", required=True)
    parser.add_argument("--log", required=True)
    parser.add_argument("--info", default="{}")
    parser.add_argument("--root", default=os.path.dirname(os.path.dirname(os.path.dirname(
        os.path.abspath(__file__)))))
    args = parser.parse_args(sys.argv[1:split])
    command = sys.argv[split + 1:]
    if not command:
        sys.exit("run_one.py: empty command")

    os.makedirs(args.out, exist_ok=True)
    keep = {os.path.abspath(args.log), os.path.abspath(args.provenance)}
    for name in os.listdir(args.out):
        path = os.path.abspath(os.path.join(args.out, name))
        if path in keep:
            continue
        if os.path.isdir(path) and not os.path.islink(path):
            shutil.rmtree(path)
        else:
            os.remove(path)

    configs = {}
    for i, a in enumerate(command[:-1]):
        if a == "--config" and os.path.isfile(command[i + 1]):
            configs[command[i + 1]] = sha256(command[i + 1])
    exe = shutil.which(command[0]) or command[0]
    started = datetime.datetime.now(datetime.timezone.utc)
    t0 = time.monotonic()
    # the refinement's BLAS gets the job's cores, no more: jobs share a node (README, --threads)
    env = dict(os.environ)
    if "--threads" in command[:-1] and "OPENBLAS_NUM_THREADS" not in env:
        env["OPENBLAS_NUM_THREADS"] = command[command.index("--threads") + 1]
    with open(args.log, "w") as log:
        log.write("$ " + " ".join(command) + "\n")
        log.flush()
        code = subprocess.call(command, stdout=log, stderr=subprocess.STDOUT, env=env)
    wall = time.monotonic() - t0
    ended = datetime.datetime.now(datetime.timezone.utc)
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)  # before any other child
    rss_kib = usage.ru_maxrss  # KiB on Linux
    rev, dirty = git_revision(args.root)
    info = json.loads(args.info)
    prov = {
        **info,
        "argv": command,
        "exit_code": code,
        "wall_s": round(wall, 3),
        "cpu_s": round(usage.ru_utime + usage.ru_stime, 3),
        "peak_rss_mib": round(rss_kib / 1024.0, 1),
        "git_revision": rev,
        "git_dirty": dirty,
        "executable": os.path.abspath(exe),
        "executable_mtime_utc": (datetime.datetime.fromtimestamp(os.path.getmtime(exe), datetime.timezone.utc)
                                 .isoformat(timespec="seconds") if os.path.exists(exe) else None),
        "config_sha256": configs,
        "machine": socket.gethostname(),
        "cpu_model": cpu_model(),
        "cpu_count": os.cpu_count(),
        "slurm_job_id": os.environ.get("SLURM_JOB_ID"),
        "openblas_num_threads": env.get("OPENBLAS_NUM_THREADS"),  # the refinement's BLAS (round-off differs)
        "started_utc": started.isoformat(timespec="seconds"),
        "ended_utc": ended.isoformat(timespec="seconds"),
    }
    tmp = args.provenance + ".tmp"
    with open(tmp, "w") as f:
        json.dump(prov, f, indent=2)
        f.write("\n")
    if code == 0:
        os.replace(tmp, args.provenance)
    else:
        os.remove(tmp)
        sys.stderr.write(f"run_one.py: exit code {code}: {' '.join(command)} (log: {args.log})\n")
        with open(args.log) as f:
            tail = f.readlines()[-15:]
        sys.stderr.write("".join(tail))
    return code


if __name__ == "__main__":
    sys.exit(main())
