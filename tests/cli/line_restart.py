#!/usr/bin/python3
"""Restart with a refined line field: the angle sweep's beams crossing at 4 degrees (angle_sweep.py),
Lagrange multipliers, B's ends pressed down by 0.4 (contact from T = 0.25, so most steps have a contact
zone shorter than A's elements and a refined field), 40 increments, a checkpoint after every step.
kill_restart.py then kills the run at random moments and restarts it: every row of every CSV must
equal the uninterrupted run's (the refinement a step starts from comes from its checkpointed points).

    line_restart.py BEAMCONTACT WORKDIR KILLS [MPIRUN...]
"""
import os
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import angle_sweep  # noqa: E402

exe, work, kills = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
angle_sweep.W = 0.4
text = angle_sweep.deck(4, "Lagrange Multiplier")
text = text.replace('<Parameter name="Number of Increments" type="int" value="10"/>',
                    '<Parameter name="Number of Increments" type="int" value="40"/>')
text = text.replace('<Parameter name="Write VTK" type="bool" value="false"/>',
                    '<Parameter name="Write VTK" type="bool" value="false"/>'
                    '<Parameter name="Checkpoint Every" type="int" value="1"/>')
assert 'value="40"' in text and "Checkpoint Every" in text
path = os.path.join(work, "line_restart.xml")
with open(path, "w") as f:
    f.write(text)
here = os.path.dirname(os.path.abspath(__file__))
sys.exit(subprocess.call([sys.executable, os.path.join(here, "kill_restart.py"), exe, path,
                          os.path.join(work, "kills"), kills] + sys.argv[4:]))
