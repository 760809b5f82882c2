"""Output/VTK Every, VTK At and VTK Compression, and the two series (beams, contact points), read back with
VTK's own XML reader on Example 1 (50 steps of T = 0.02, contact from about T = 0.2):

1. raw and compressed: the same deck with VTK Compression false and true writes, for every step of both
   series, files whose points, cells and every point and cell array VTK reads back bit for bit equal
   (zlib is lossless and both write Float64); the compressed files carry VTK's zlib compressor and are
   smaller;
2. the series: results.pvd lists the beams only (no vertex cell, no contact array), contact.pvd the
   contact points only (one vertex cell per point, as many as contact_points.csv has active rows in
   that step, at their positions), both with the step's load factor as field data;
3. VTK Every 7 with VTK At {0.25, 0.5, 0.55}: both collections list exactly T = 0, the steps whose number
   7 divides, the first step at or beyond each listed T (from steps.csv: the step after the last one
   below it) and the last step (50), and their files equal those of the run that wrote every step;
4. restart: that run, restarted from its checkpoint at step 40 (Checkpoint Every 20), ends with the
   same collections and files as without the restart.
"""
import csv
import re
import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

exe, base, work = sys.argv[1], Path(sys.argv[2]), Path(sys.argv[3])
shutil.rmtree(work, ignore_errors=True)
work.mkdir(parents=True)


def run(name, output, *extra):
    text = base.read_text().replace(
        '<ParameterList name="Output">', '<ParameterList name="Output">' + "".join(output), 1)
    deck = work / f"{name}.xml"
    deck.write_text(text)
    out = work / name
    subprocess.run([exe, "run", str(deck), "--output", str(out), "--quiet", *extra], check=True,
                   stdout=subprocess.DEVNULL)
    return out


def collection(results, series):
    return [(float(d.get("timestep")), d.get("file"))
            for d in ET.parse(results / f"{series}.pvd").getroot().findall("./Collection/DataSet")]


def read(path):
    """Everything VTK reads from a file: points, cell types and connectivity, every array."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    assert reader.GetErrorCode() == 0, path
    grid = reader.GetOutput()
    data = {"points": vtk_to_numpy(grid.GetPoints().GetData()) if grid.GetNumberOfPoints() else np.zeros((0, 3)),
            "types": np.array([grid.GetCellType(i) for i in range(grid.GetNumberOfCells())]),
            "cells": [tuple(grid.GetCell(i).GetPointId(k) for k in range(grid.GetCell(i).GetNumberOfPoints()))
                      for i in range(grid.GetNumberOfCells())]}
    for kind, arrays in (("point", grid.GetPointData()), ("cell", grid.GetCellData()), ("field", grid.GetFieldData())):
        for k in range(arrays.GetNumberOfArrays()):
            a = arrays.GetArray(k)
            data[f"{kind}:{a.GetName()}"] = vtk_to_numpy(a)
    return data


def same(a, b, what):
    assert a.keys() == b.keys(), (what, sorted(a.keys() ^ b.keys()))
    for k in a:
        if k == "cells":
            assert a[k] == b[k], (what, k)
        else:
            assert a[k].dtype == b[k].dtype and np.array_equal(a[k], b[k]), (what, k)


every = ['<Parameter name="Write VTK" type="bool" value="true"/>']
raw = run("raw", every + ['<Parameter name="VTK Compression" type="bool" value="false"/>'])
packed = run("compressed", every)  # the default: compressed

# 1. Raw and compressed files hold the same values, for every step of both series.
raw_bytes = packed_bytes = 0
for series in ("results", "contact"):
    a, b = collection(raw, series), collection(packed, series)
    assert len(a) == 51 and a == b, (series, len(a))
    for T, file in a:
        assert 'compressor="vtkZLibDataCompressor"' in (packed / file).read_bytes()[:400].decode("latin-1")
        assert "compressor" not in (raw / file).read_bytes()[:400].decode("latin-1")
        same(read(raw / file), read(packed / file), file)
        raw_bytes += (raw / file).stat().st_size
        packed_bytes += (packed / file).stat().st_size
print(f"102 files per run read back equal; raw {raw_bytes} bytes, compressed {packed_bytes} ({packed_bytes / raw_bytes:.2f})")
assert packed_bytes < 0.8 * raw_bytes

# 2. Beams and contact points in their own series.
rows = list(csv.DictReader(open(packed / "contact_points.csv")))
contact_steps = 0
for (T, beams_file), (Tc, contact_file) in zip(collection(packed, "results"), collection(packed, "contact")):
    step = int(re.search(r"_(\d+)\.vtu$", beams_file).group(1))
    assert contact_file == f"vtk/contact_{step:05d}.vtu" and T == Tc
    beams, contact = read(packed / beams_file), read(packed / contact_file)
    for d in (beams, contact):
        assert d["field:load factor"][0] == T and d["field:step"][0] == step
    assert vtk.VTK_VERTEX not in beams["types"] and not any(k.startswith("point:contact") for k in beams)
    assert sorted(beams["types"]) == [vtk.VTK_LINE] * 20 + [vtk.VTK_HEXAHEDRON] * 20  # 20 rectangular elements
    active = [r for r in rows if int(r["step"]) == step and r["active"] == "1"]
    assert list(contact["types"]) == [vtk.VTK_VERTEX] * len(active), (step, len(active))
    assert "point:contact force" in contact and "cell:beam" not in contact
    for r, p in zip(active, contact["points"]):
        assert np.abs(p - [float(r["x"]), float(r["y"]), float(r["z"])]).max() < 1e-8
    contact_steps += bool(active)
assert contact_steps > 10, contact_steps
print(f"beams in results.pvd, contact points in contact.pvd ({contact_steps} steps with contact)")

# 3. VTK Every 7, VTK At {0.25, 0.5, 0.55}: T = 0, multiples of 7, the first step at or beyond each T, the last.
chosen = ['<Parameter name="VTK Every" type="int" value="7"/>',
          '<Parameter name="VTK At" type="Array(double)" value="{0.25, 0.5, 0.55}"/>',
          '<Parameter name="Checkpoint Every" type="int" value="20"/>']
sparse = run("sparse", chosen)
steps = [(int(r["step"]), float(r["T"])) for r in csv.DictReader(open(sparse / "steps.csv"))]
expected = {0} | {s for s, _ in steps if s % 7 == 0} | {steps[-1][0]}
for at in (0.25, 0.5, 0.55):
    expected.add(next(s for s, T in steps if T >= at - 1e-12))
expected = sorted(expected)
print(f"VTK Every 7, VTK At 0.25, 0.5, 0.55: steps {expected}")
assert 13 in expected and 25 in expected and 28 in expected and 50 in expected
every_step = {series: dict((f, T) for T, f in collection(packed, series)) for series in ("results", "contact")}


def check_sparse(results, what):
    for series, prefix in (("results", "step"), ("contact", "contact")):
        listed = collection(results, series)
        assert [f for _, f in listed] == [f"vtk/{prefix}_{s:05d}.vtu" for s in expected], (what, series, listed)
        for T, f in listed:
            assert every_step[series][f] == T
            same(read(results / f), read(packed / f), f"{what} {f}")
        on_disk = sorted(p.name for p in (results / "vtk").glob(f"{prefix}_*.vtu"))
        assert on_disk == [Path(f).name for _, f in listed], (what, series, on_disk)


check_sparse(sparse, "VTK Every/At")

# 4. Restarted from the checkpoint at step 40: the same collections and files.
before = {p.name: p.stat().st_mtime_ns for p in (sparse / "vtk").iterdir()}
subprocess.run([exe, "run", str(work / "sparse.xml"), "--restart", str(sparse), "--quiet"], check=True,
               stdout=subprocess.DEVNULL)
check_sparse(sparse, "restarted")
after = {p.name: p.stat().st_mtime_ns for p in (sparse / "vtk").iterdir()}
assert after.keys() == before.keys()
for name, t in after.items():  # steps up to the checkpoint's kept, the later ones written again
    assert (t == before[name]) == (int(name[-9:-4]) <= 40), name
print("restart from step 40: the same files")
print("1 passed, 0 failed")
