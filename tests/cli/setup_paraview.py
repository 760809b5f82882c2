#!/usr/bin/python3
"""The set-up script (cmake/setup-debian.sh) beside ParaView, run against stand-ins for dpkg-query,
apt-get and sudo (first on PATH: nothing is installed or removed) and, where asked, an import hook that
makes Python's vtk module unimportable:
- python3-paraview installed, its vtk importable, python3-numpy missing: apt-get is asked for
  python3-numpy only (with --no-remove), never for python3-vtk9;
- python3-paraview installed, vtk not importable: python3-vtk9 is not asked for (it conflicts with
  python3-paraview), and a line says to reinstall python3-paraview;
- no python3-paraview, vtk not importable: python3-vtk9 is asked for, with --no-remove;
- nothing missing: apt-get is not called;
and no apt-get call ever removes or purges a package.

    setup_paraview.py SOURCE_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys

src, work = (os.path.abspath(a) for a in sys.argv[1:3])
shutil.rmtree(work, ignore_errors=True)
fake = os.path.join(work, "bin")
hook = os.path.join(work, "hook")
os.makedirs(fake)
os.makedirs(hook)
log = os.path.join(work, "apt.log")
scripts = {
    # Every package installed except those in FAKE_MISSING; python3-paraview only with FAKE_PARAVIEW=1.
    "dpkg-query": '#!/bin/sh\npkg="$3"\n'
                  'if [ "$pkg" = python3-paraview ] && [ "$FAKE_PARAVIEW" != 1 ]; then exit 1; fi\n'
                  'case ",$FAKE_MISSING," in *",$pkg,"*) exit 1;; esac\n'
                  "printf 'install ok installed'\n",
    "apt-get": f'#!/bin/sh\necho "$*" >> "{log}"\n',
    "sudo": '#!/bin/sh\nexec "$@"\n',
}
for name, text in scripts.items():
    with open(os.path.join(fake, name), "w") as f:
        f.write(text)
    os.chmod(os.path.join(fake, name), 0o755)
with open(os.path.join(hook, "sitecustomize.py"), "w") as f:
    f.write("import sys\n\n\nclass Hook:\n    def find_spec(self, name, path=None, target=None):\n"
            "        if name.split('.')[0] == 'vtk':\n            raise ModuleNotFoundError(name=name)\n\n\n"
            "sys.meta_path.insert(0, Hook())\n")
failures = []


def setup(paraview, vtk, missing=""):
    if os.path.exists(log):
        os.remove(log)
    env = dict(os.environ, PATH=fake + os.pathsep + os.environ["PATH"], FAKE_PARAVIEW="1" if paraview else "0",
               FAKE_MISSING=missing, PYTHONPATH="" if vtk else hook)
    r = subprocess.run(["bash", os.path.join(src, "cmake", "setup-debian.sh")], capture_output=True, text=True,
                       env=env)
    calls = open(log).read().splitlines() if os.path.exists(log) else []
    installs = [c for c in calls if c.startswith("install")]
    print(f"paraview={paraview} vtk={vtk} missing={missing!r}: exit {r.returncode}, apt-get {calls}, "
          f"stdout {r.stdout.strip()!r}, stderr {r.stderr.strip()!r}")
    if r.returncode != 0:
        failures.append(f"exit {r.returncode}")
    if any(w in c.split() for c in calls for w in ("remove", "purge", "autoremove")):
        failures.append(f"apt-get asked to remove: {calls}")
    if any("--no-remove" not in c.split() for c in installs):
        failures.append(f"apt-get install without --no-remove: {installs}")
    return r, " ".join(installs).split()


r, asked = setup(True, True, "python3-numpy")
if "python3-numpy" not in asked or "python3-vtk9" in asked:
    failures.append(f"ParaView's vtk importable: asked for {asked}")
r, asked = setup(True, False)
if asked or "reinstall python3-paraview" not in r.stderr.replace("--reinstall ", "reinstall "):
    failures.append(f"ParaView's vtk not importable: asked for {asked}, stderr {r.stderr!r}")
r, asked = setup(False, False)
if "python3-vtk9" not in asked:
    failures.append(f"no ParaView, no vtk: asked for {asked}")
r, asked = setup(False, True)
if asked or os.path.exists(log):
    failures.append(f"nothing missing: apt-get called ({asked})")
if failures:
    sys.exit("FAIL: " + "; ".join(failures))
print("ok: python3-paraview's vtk accepted, python3-vtk9 never asked for beside it, nothing removed")
