"""The third-party Python modules of BeamContact's scripts (render_stages.py, study_report.py,
paraview_views.py): a module that cannot be imported is one line naming the Debian package to install,
and exit code 4."""
import importlib
import os
import sys

# The Debian package of each third-party module these scripts import.
DEBIAN_PACKAGES = {"numpy": "python3-numpy", "matplotlib": "python3-matplotlib", "mpl_toolkits": "python3-matplotlib",
                   "vtk": "python3-vtk9", "vtkmodules": "python3-vtk9", "paraview": "paraview"}
# ParaView's Python package (python3-paraview, pulled in by paraview) has its own vtk module and conflicts
# with python3-vtk9: where it is installed, its vtk is the one to (re)install.
if os.path.exists("/var/lib/dpkg/info/python3-paraview.list"):
    DEBIAN_PACKAGES.update({"vtk": "python3-paraview", "vtkmodules": "python3-paraview"})


def need(module, who, hint=""):
    """Imports `module`; when it cannot be (not installed, or broken: any error while importing it), one
    line "beamcontact: WHO: ..." naming the Debian package to install (then `hint`) and exit 4."""
    try:
        return importlib.import_module(module)
    except Exception as e:  # noqa: BLE001 - one line, not a traceback
        missing = isinstance(e, ModuleNotFoundError) and e.name
        top = (e.name if missing else module).split(".")[0]
        package = DEBIAN_PACKAGES.get(top)
        if missing:
            why, verb, flag = "is not installed", "install", ""
        else:
            why, verb, flag = f"cannot be loaded ({type(e).__name__}: {(str(e) + chr(10)).splitlines()[0]})", \
                "reinstall", " --reinstall"
        how = f"{verb} the Debian package {package} (apt install{flag} {package})" if package else f"{verb} {top}"
        print(f"beamcontact: {who}: the Python module {top} {why}; {how}{hint}", file=sys.stderr)
        sys.exit(4)
