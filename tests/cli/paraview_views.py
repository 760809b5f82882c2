#!/usr/bin/python3
"""ParaView's standard views (drivers/paraview_views.py under pvpython) of Example 1's results, where
ParaView is installed; skipped (exit 77, CTest's SKIP_RETURN_CODE) where `pvpython` is not on PATH, or
where there is no display and no xvfb-run to give it one:
- exit 0, and one PNG per view (iso, xz, xy) and stage (T = 0.5, 1), each of the size asked
  (640 x 480), each more than a background (at least 50 colours), and the iso view at T = 1 with the
  contact-force arrows' crimson (at least 20 pixels within 40 of (220, 20, 61) in each channel).

    paraview_views.py SCRIPTS_DIR RESULTS_DIR WORKDIR
"""
import os
import shutil
import subprocess
import sys

scripts, results, work = (os.path.abspath(a) for a in sys.argv[1:4])
pvpython = shutil.which("pvpython")
if not pvpython:
    print("SKIP: pvpython is not on PATH (ParaView is not installed; the Debian package is paraview)")
    sys.exit(77)
command = [pvpython, "--force-offscreen-rendering"]
if not os.environ.get("DISPLAY") and not os.environ.get("WAYLAND_DISPLAY"):
    if not shutil.which("xvfb-run"):
        print("SKIP: no display for ParaView's renderer and no xvfb-run (Debian package xvfb)")
        sys.exit(77)
    command = ["xvfb-run", "-a"] + command
from PIL import Image  # noqa: E402 - matplotlib's dependency, with /usr/bin/python3

shutil.rmtree(work, ignore_errors=True)
os.makedirs(work)
r = subprocess.run(command + [os.path.join(scripts, "paraview_views.py"), results, work, "--stages", "0.5,1",
                              "--size", "640x480"], capture_output=True, text=True, timeout=300)
print(r.stdout)
print(r.stderr)
if r.returncode != 0:
    sys.exit(f"FAIL: paraview_views.py exit {r.returncode}")
failures = []
for view in ("iso", "xz", "xy"):
    for T in ("0.5", "1"):
        path = os.path.join(work, f"{view}_T{T}.png")
        if not os.path.isfile(path):
            failures.append(f"{path} not written")
            continue
        with Image.open(path) as png:
            rgb = png.convert("RGB")
            colours = rgb.getcolors(1 << 20) or []
            if png.size != (640, 480) or len(colours) < 50:
                failures.append(f"{path}: {png.size}, {len(colours)} colours")
            if (view, T) == ("iso", "1"):
                crimson = sum(n for n, c in colours if all(abs(a - b) <= 40 for a, b in zip(c, (220, 20, 61))))
                if crimson < 20:
                    failures.append(f"{path}: {crimson} crimson pixels (the contact-force arrows)")
if failures:
    sys.exit("FAIL: " + "; ".join(failures))
print("ok: six views of Example 1 from pvpython, 640 x 480, with the contact-force arrows")
