#!/usr/bin/python3
"""A run that no launcher started is an MPI singleton; Open MPI 4 would fork its daemon (orted) for it
before MPI_Init returns, and beamcontact starts it without (OMPI_MCA_ess_singleton_isolated, set
before MPI_Init when no launcher's variables are present: drivers/beamcontact.cpp). Checked on the
process tree: while `beamcontact run` runs Example 1, its descendants are read from /proc every
millisecond or so (a daemon would live from MPI_Init to MPI_Finalize, the whole run).
  - Without the variable in the environment: the run completes and no descendant is an orted.
  - With OMPI_MCA_ess_singleton_isolated=0 given by the user (kept: the control that shows the check
    sees a daemon when there is one): the run completes and an orted was among its descendants.
Usage: singleton_start.py BEAMCONTACT DECK WORK
"""
import os
import subprocess
import sys
import time


def descendants(pid):
    """{pid: command name} of the process tree below `pid` (those that can be read)."""
    found, todo = {}, [pid]
    while todo:
        p = todo.pop()
        try:
            tasks = os.listdir(f"/proc/{p}/task")
        except OSError:
            continue
        for t in tasks:
            try:
                with open(f"/proc/{p}/task/{t}/children") as f:
                    kids = [int(k) for k in f.read().split()]
            except OSError:
                continue
            for k in kids:
                try:
                    with open(f"/proc/{k}/comm") as f:
                        found[k] = f.read().strip()
                except OSError:
                    found[k] = "?"
                todo.append(k)
    return found


def run_watched(exe, deck, out, env):
    child = subprocess.Popen([exe, "run", deck, "--output", out, "--quiet"], env=env, stdout=subprocess.PIPE,
                             stderr=subprocess.STDOUT)
    seen = {}
    while child.poll() is None:
        seen.update(descendants(child.pid))
        time.sleep(0.001)
    output = child.stdout.read().decode()
    return child.returncode, sorted(set(seen.values())), output


def main():
    exe, deck, work = sys.argv[1:4]
    os.makedirs(work, exist_ok=True)
    # As a shell started it: no launcher's variables, no ess_singleton_isolated of its own.
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("OMPI_COMM_WORLD_", "PMIX_", "PMI_", "OMPI_MCA_ess_singleton"))}
    failures = 0
    code, names, output = run_watched(exe, deck, os.path.join(work, "isolated"), env)
    print(f"singleton start: exit {code}, descendants {names or 'none'}")
    if code != 0 or "orted" in names:
        print(output)
        failures += 1
    control = dict(env, OMPI_MCA_ess_singleton_isolated="0")
    code, names, output = run_watched(exe, deck, os.path.join(work, "daemon"), control)
    print(f"with OMPI_MCA_ess_singleton_isolated=0 (the user's): exit {code}, descendants {names or 'none'}")
    if code != 0 or "orted" not in names:
        print(output)
        failures += 1
    if failures:
        sys.exit(f"{failures} check(s) failed")
    print("ok")


if __name__ == "__main__":
    main()
