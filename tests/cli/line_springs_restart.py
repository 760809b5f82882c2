#!/usr/bin/python3
"""Restart with Penalty's springs on the line's nodes (Line Springs = Nodes) in partial slip: a rod
(circle r 0.5, 20 elements, E 1e5) lying on a ground held at every node, pressed by q = 0.01 per length
while T goes to 0.5 (nodal forces, half at the ends), then pulled at its far end along X by 0.15 while
T goes to 1, its near end held along X, friction 0.3 (Isotropic Coulomb): 20 increments, a checkpoint
after every step. The line nodes keep their active set, stick and slip and their friction multipliers
of the last converged step (the springs' Lambda_T,n) in the checkpoint. kill_restart.py kills the run
at random moments and restarts it: every row of every CSV must equal the uninterrupted run's.

    line_springs_restart.py BEAMCONTACT WORKDIR KILLS [MPIRUN...]
"""
import os
import subprocess
import sys

exe, work, kills = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
n, q = 20, 0.01
h = 100.0 / n
section = ('<ParameterList name="Section"><Parameter name="Shape" type="string" value="Circle"/>'
           '<Parameter name="Radius" type="double" value="0.5"/></ParameterList>'
           '<ParameterList name="Material"><Parameter name="Young\'s Modulus" type="double" value="1e5"/>'
           '<Parameter name="Poisson\'s Ratio" type="double" value="0.3"/></ParameterList>')


def beam(name, z):
    return (f'<ParameterList name="{name}"><Parameter name="Start" type="Array(double)" value="{{0, 0, {z}}}"/>'
            f'<Parameter name="End" type="Array(double)" value="{{100, 0, {z}}}"/>'
            f'<Parameter name="Elements" type="int" value="{n}"/>{section}</ParameterList>')


def support(b, i, fixed):
    return (f'<ParameterList name="{b} {i}"><Parameter name="Beam" type="string" value="{b}"/>'
            f'<Parameter name="Node" type="string" value="{i}"/>'
            f'<Parameter name="Fixed" type="string" value="{fixed}"/></ParameterList>')


supports = "".join(support("ground", i, "all") +
                   support("rod", i, "ux uy uz rx rz" if i == 0 else "uy uz rx rz" if i == n else "uy rx rz")
                   for i in range(n + 1))
loads = "".join(
    f'<ParameterList name="press {i}"><Parameter name="Beam" type="string" value="rod"/>'
    f'<Parameter name="Node" type="string" value="{i}"/>'
    f'<Parameter name="Force" type="Array(double)" value="{{0, 0, {-q * h * (0.5 if i in (0, n) else 1.0)}}}"/>'
    '<Parameter name="Load Curve" type="Array(double)" value="{0, 0, 0.5, 1, 1, 1}"/></ParameterList>'
    for i in range(n + 1))
loads += ('<ParameterList name="pull"><Parameter name="Beam" type="string" value="rod"/>'
          f'<Parameter name="Node" type="string" value="{n}"/>'
          '<Parameter name="Force" type="Array(double)" value="{0.15, 0, 0}"/>'
          '<Parameter name="Load Curve" type="Array(double)" value="{0, 0, 0.5, 0, 1, 1}"/></ParameterList>')
deck = f'''<ParameterList name="BeamContact">
<ParameterList name="Beams">{beam("ground", 0)}{beam("rod", 1)}</ParameterList>
<ParameterList name="Supports">{supports}</ParameterList>
<ParameterList name="Loads">{loads}</ParameterList>
<ParameterList name="Contact"><Parameter name="Line Gauss Points" type="int" value="6"/>
<Parameter name="Allow Initial Penetration" type="bool" value="true"/>
<ParameterList name="Pairs"><ParameterList name="line"><Parameter name="Beam A" type="string" value="ground"/>
<Parameter name="Beam B" type="string" value="rod"/><Parameter name="Friction Coefficient" type="double" value="0.3"/>
</ParameterList></ParameterList>
<ParameterList name="Enforcement"><Parameter name="Type" type="string" value="Penalty"/>
<ParameterList name="Penalty"><Parameter name="Normal Penalty Parameter" type="double" value="1e4"/>
<Parameter name="Tangential Penalty Parameter" type="double" value="1e3"/>
<Parameter name="Line Springs" type="string" value="Nodes"/></ParameterList></ParameterList></ParameterList>
<ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value="20"/></ParameterList>
<ParameterList name="Output"><Parameter name="Write VTK" type="bool" value="false"/>
<Parameter name="Checkpoint Every" type="int" value="1"/></ParameterList>
</ParameterList>
'''
path = os.path.join(work, "line_springs_restart.xml")
with open(path, "w") as f:
    f.write(deck)
here = os.path.dirname(os.path.abspath(__file__))
sys.exit(subprocess.call([sys.executable, os.path.join(here, "kill_restart.py"), exe, path,
                          os.path.join(work, "kills"), kills] + sys.argv[4:]))
