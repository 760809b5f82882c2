"""Reads a run's VTK output back with VTK's own XML reader and checks it against the roll-up deck's
closed form: 20 hexahedra (one per element, rectangular section), displacement zero at T = 0, and at
T = 1 the tip section back at the clamp (displacement (-100, 0, 0) for every point of the tip face,
since a full 2 pi turn leaves the section's orientation unchanged). The files hold the reference
places (the same in every step) with the displacement, and the load factor as field data; each
element also has a centreline line cell, its section forces (pure bending by the tip moment) and its
nodal triads."""
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy

results = Path(sys.argv[1])
pvd = ET.parse(results / "results.pvd").getroot()
datasets = pvd.findall("./Collection/DataSet")
assert len(datasets) == 21, f"results.pvd lists {len(datasets)} files, expected 21 (T = 0 and 20 steps)"
assert float(datasets[-1].get("timestep")) == 1.0


def read(name):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(results / name))
    reader.Update()
    grid = reader.GetOutput()
    points = vtk_to_numpy(grid.GetPoints().GetData())
    disp = vtk_to_numpy(grid.GetPointData().GetArray("displacement"))
    T = grid.GetFieldData().GetArray("load factor").GetValue(0)
    return grid, points, disp, T


grid0, p0, d0, T0 = read(datasets[0].get("file"))
assert T0 == 0.0
types = [grid0.GetCellType(i) for i in range(grid0.GetNumberOfCells())]
assert len(types) == 40, len(types)  # per element a hexahedron (the section) and a line (the centreline)
assert types.count(vtk.VTK_HEXAHEDRON) == 20 and types.count(vtk.VTK_LINE) == 20, types
assert np.abs(d0).max() == 0.0
# Reference section: 1 x 1 around the axis y = z = 0.
assert np.isclose(np.abs(p0[:, 1]).max(), 0.5) and np.isclose(np.abs(p0[:, 2]).max(), 0.5)

grid1, r1, d1, T1 = read(datasets[-1].get("file"))
assert T1 == 1.0
assert grid1.GetNumberOfPoints() == grid0.GetNumberOfPoints()
assert np.abs(r1 - p0).max() < 1e-9, "the points are not the reference places"
p1 = r1 + d1  # deformed
tip_face = np.isclose(p0[:, 0], 100.0)
assert tip_face.sum() == 5  # centre and four corners of the last element's end
err = np.abs(d1[tip_face] - np.array([-100.0, 0.0, 0.0])).max()
print(f"tip face points: {tip_face.sum()}, max |u - (-100, 0, 0)| = {err:.2e}")
assert err < 1e-6, err
# Mid-span face: the beam's section stays 1 x 1 (rigid section), so corner-to-centre distances keep
# their reference length sqrt(0.5).
mid = np.isclose(p0[:, 0], 50.0)
centre = p1[mid & np.isclose(np.abs(p0[:, 1]) + np.abs(p0[:, 2]), 0.0)][0]
corners = p1[mid & ~np.isclose(np.abs(p0[:, 1]) + np.abs(p0[:, 2]), 0.0)]
assert np.allclose(np.linalg.norm(corners - centre, axis=1), np.sqrt(0.5), atol=1e-9)
# Section forces: pure bending by the tip moment M = 2 pi E I / L (157.0796) in every element, about
# the section's y axis; no axial force, shear or torque. Triads: e1 along the beam, turned by pi at
# mid-span (pointing along -X) and by 2 pi at the tip (back along +X).
M = 2 * np.pi * 30000.0 * (1.0 / 12.0) / 100.0
cells = grid1.GetCellData()
for name, expected in (("bending moment y", -M), ("bending moment z", 0.0), ("axial force", 0.0),
                       ("shear force y", 0.0), ("shear force z", 0.0), ("torque", 0.0)):
    values = vtk_to_numpy(cells.GetArray(name))
    print(f"{name}: {values.min():.9g} .. {values.max():.9g} (closed form {expected:.9g})")
    assert np.abs(values - expected).max() < 1e-9 * M, name
e1 = vtk_to_numpy(grid1.GetPointData().GetArray("triad e1"))
assert np.abs(e1[tip_face] - [1.0, 0.0, 0.0]).max() < 1e-6
assert np.abs(e1[mid] - [-1.0, 0.0, 0.0]).max() < 1e-6
print("1 passed, 0 failed")
