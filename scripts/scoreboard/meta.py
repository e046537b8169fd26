#!/usr/bin/env python3
"""The header of a scoreboard evaluation: OUT/scoreboard.json (scripts/scoreboard.sh writes it).

    meta.py start OUT --panel P --command "..." --rasm RASM --jobs J --omp T [--resume]
    meta.py finish OUT --wall-s S

start: the code's commit (`git rev-parse --short HEAD`, "-dirty" when tracked files differ from
it), the date, the machine (nproc, CPU model, memory), the binary's `rasm --version`, the panel and
the exact command. With --resume the first session's fields are kept and one more session is
recorded (a different commit is reported: rows of two commits in one table). finish: adds the
session's wall time. Python 3 standard library only.
"""

import datetime
import json
import os
import subprocess
import sys


def sh(*cmd):
    try:
        return subprocess.run(cmd, capture_output=True, text=True, check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return None


def commit(root):
    head = sh("git", "-C", root, "rev-parse", "--short", "HEAD")
    if head is None:
        return "unknown"
    dirty = sh("git", "-C", root, "status", "--porcelain", "--untracked-files=no")
    return head + ("-dirty" if dirty else "")


def machine():
    cpu, mem = None, None
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
        for line in open("/proc/meminfo"):
            if line.startswith("MemTotal"):
                mem = round(int(line.split()[1]) / 1024 / 1024, 1)
    except OSError:
        pass
    return {"nproc": len(os.sched_getaffinity(0)), "cpu": cpu, "mem_gib": mem}


def now():
    return datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")


def main(argv):
    import argparse
    ap = argparse.ArgumentParser()
    ap.add_argument("what", choices=("start", "finish"))
    ap.add_argument("out")
    ap.add_argument("--panel")
    ap.add_argument("--command")
    ap.add_argument("--rasm")
    ap.add_argument("--jobs", type=int)
    ap.add_argument("--omp")
    ap.add_argument("--resume", action="store_true")
    ap.add_argument("--wall-s", type=float)
    a = ap.parse_args(argv[1:])
    path = os.path.join(a.out, "scoreboard.json")
    old = None
    if os.path.exists(path):
        with open(path) as f:
            old = json.load(f)
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    if a.what == "start":
        session = {"command": a.command, "started": now(), "commit": commit(root),
                   "machine": machine(), "jobs": a.jobs, "omp_num_threads": a.omp,
                   "rasm": a.rasm,
                   "rasm_version": (sh(a.rasm, "--version") or "").split("\n")[0] or None}
        if a.resume and old:
            if old.get("panel") != a.panel:
                sys.exit(f"scoreboard: {a.out} holds a {old.get('panel')} panel, not {a.panel} "
                         "(--fresh to start over)")
            doc = old
            if session["commit"] != doc["sessions"][0]["commit"]:
                print(f"scoreboard: WARNING: resuming rows made at "
                      f"{doc['sessions'][0]['commit']} with the code at {session['commit']}: "
                      "the table mixes both", file=sys.stderr)
        else:
            doc = {"panel": a.panel, "sessions": []}
        doc["sessions"].append(session)
    else:
        doc = old
        doc["sessions"][-1]["finished"] = now()
        doc["sessions"][-1]["wall_s"] = a.wall_s
    with open(path + ".tmp", "w") as f:
        json.dump(doc, f, indent=1)
        f.write("\n")
    os.replace(path + ".tmp", path)


if __name__ == "__main__":
    main(sys.argv)
