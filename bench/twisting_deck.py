#!/usr/bin/python3
"""The twisting-rods deck (input/twisting_rods.xml is this script's output with its defaults):
two parallel circular steel rods in contact along their length, their bottom ends clamped, their top
ends stretched by 1 % and carried around a circle about the common axis by an angle THETA, the
clamps turning with them (a rotation about z only, which increments compose exactly). Away from the
ends (boundary layers about sqrt(EI / N) = 5 radii long) the rods form a uniform double helix
(docs/contact.md, "Twisting rods"). Rod 2 has one element fewer than rod 1: on matching meshes each
node of rod 1 lies exactly on a segment plane of rod 2 (docs/contact.md). Units: mm, N, MPa.
Usage: twisting_deck.py [--elements N] [--increments N] [--type STRATEGY] > deck.xml
"""
import argparse
import math

R = 1.0  # radius of each rod [mm]; their axes start 2 R apart, at x = +R and x = -R
L = 100.0  # length [mm] (100 R: the ends' boundary layers, about 5 R long, have died out in the middle)
E, NU = 200000.0, 0.3  # [MPa]
STRETCH = 0.01  # axial displacement of the top ends over L
THETA = math.pi  # the top ends' turn about the z axis at T = 1 [rad]
CURVE_POINTS = 100  # load-curve intervals: every 1, 2, 4, 5, 10, 20, 25, 50 or 100 increments land on the circle
EPS_N = 1e4  # penalty per unit length of line [N/mm^2]
GAUSS = 2  # Gauss points per segment: the helix's line load is uniform; each point costs about 0.3 ms per assembly


def curve(f):
    pts = []
    for k in range(CURVE_POINTS + 1):
        T = k / CURVE_POINTS
        pts.append(f"{T:.17g}, {f(T):.17g}")
    return "{" + ", ".join(pts) + "}"


def beam(name, x, elements):
    return f"""    <ParameterList name="{name}">
      <Parameter name="Start" type="Array(double)" value="{{{x:.17g}, 0.0, 0.0}}"/>          <!-- mm -->
      <Parameter name="End" type="Array(double)" value="{{{x:.17g}, 0.0, {L:.17g}}}"/>
      <Parameter name="Elements" type="int" value="{elements}"/>
      <ParameterList name="Section">
        <Parameter name="Shape" type="string" value="Circle"/>
        <Parameter name="Radius" type="double" value="{R:.17g}"/>                    <!-- mm -->
      </ParameterList>
      <ParameterList name="Material">
        <Parameter name="Young's Modulus" type="double" value="{E:.17g}"/>           <!-- MPa -->
        <Parameter name="Poisson's Ratio" type="double" value="{NU:.17g}"/>
      </ParameterList>
    </ParameterList>
"""


def top(name, x):
    # The top node of the rod starting at (x, 0): on the circle of radius |x| at angle phi0 + theta T.
    phi0 = 0.0 if x > 0 else math.pi
    ux = curve(lambda T: abs(x) * math.cos(phi0 + THETA * T) - x)
    uy = curve(lambda T: abs(x) * math.sin(phi0 + THETA * T))
    return f"""    <ParameterList name="{name} top x">   <!-- ux = R cos(phi0 + theta T) - x0, curve times 1 mm -->
      <Parameter name="Beam" type="string" value="{name}"/>
      <Parameter name="Node" type="string" value="end"/>
      <Parameter name="Fixed" type="string" value="ux"/>
      <Parameter name="Displacement" type="Array(double)" value="{{1.0, 0.0, 0.0}}"/>
      <Parameter name="Load Curve" type="Array(double)" value="{ux}"/>
    </ParameterList>
    <ParameterList name="{name} top y">   <!-- uy = R sin(phi0 + theta T) - y0 -->
      <Parameter name="Beam" type="string" value="{name}"/>
      <Parameter name="Node" type="string" value="end"/>
      <Parameter name="Fixed" type="string" value="uy"/>
      <Parameter name="Displacement" type="Array(double)" value="{{0.0, 1.0, 0.0}}"/>
      <Parameter name="Load Curve" type="Array(double)" value="{uy}"/>
    </ParameterList>
    <ParameterList name="{name} top z">   <!-- the stretch and the clamp's turn about z, linear in T -->
      <Parameter name="Beam" type="string" value="{name}"/>
      <Parameter name="Node" type="string" value="end"/>
      <Parameter name="Fixed" type="string" value="uz rx ry rz"/>
      <Parameter name="Displacement" type="Array(double)" value="{{0.0, 0.0, {STRETCH * L:.17g}}}"/>  <!-- mm -->
      <Parameter name="Rotation" type="Array(double)" value="{{0.0, 0.0, {THETA:.17g}}}"/>  <!-- rad -->
    </ParameterList>
    <ParameterList name="{name} bottom">   <!-- clamped -->
      <Parameter name="Beam" type="string" value="{name}"/>
      <Parameter name="Node" type="string" value="start"/>
      <Parameter name="Fixed" type="string" value="all"/>
    </ParameterList>
"""


def deck(elements=16, increments=10, strategy="Penalty", eps_n=EPS_N, gauss=GAUSS, elements2=None):
    elements2 = elements - 1 if elements2 is None else elements2
    rod2middle = "" if elements2 % 2 else """      <ParameterList name="rod2 middle">
        <Parameter name="Beam" type="string" value="rod2"/>
        <Parameter name="Node" type="string" value="middle"/>
      </ParameterList>
"""
    text = f"""<!-- Twisting rods (bench/twisting_deck.py writes this deck; docs/contact.md, "Twisting rods"): two
     parallel circular steel rods (radius {R:g} mm, length {L:g} mm, E {E:g} MPa, nu {NU:g}), axes {2 * R:g} mm apart
     (touching along their length at T = 0), bottom ends clamped; the top ends are stretched by
     {STRETCH * 100:g} % and carried around the circle of radius {R:g} mm about the common axis (z) by
     theta = {THETA:.6g} rad, their clamps turning by theta about z (two supports per node, one per component,
     with load curves of {CURVE_POINTS} intervals: 10, 20 and 50 increments land on the circle). Away from
     the ends (boundary layers about sqrt(EI / N) = 5 radii long) the rods form a uniform double helix of
     radius {R:g} mm, pressed together by a uniform line load (closed form in docs/contact.md, "Twisting
     rods"; tests/regression/test_twisting_rods.cpp). Rod 1 has {elements} elements, rod 2 {elements2}
     (on matching meshes rod 1's nodes lie exactly on rod 2's segment planes). Frictionless.
     Units: mm, N, MPa. -->
<ParameterList name="BeamContact">
  <ParameterList name="Beams">
{beam("rod1", R, elements)}{beam("rod2", -R, elements2)}  </ParameterList>
  <ParameterList name="Supports">
{top("rod1", R)}{top("rod2", -R)}  </ParameterList>
  <ParameterList name="Contact">
    <Parameter name="Line Gauss Points" type="int" value="{gauss}"/>
    <ParameterList name="Pairs">
      <ParameterList name="rods">
        <Parameter name="Beam A" type="string" value="rod1"/>
        <Parameter name="Beam B" type="string" value="rod2"/>
        <Parameter name="Friction Coefficient" type="double" value="0.0"/>
      </ParameterList>
    </ParameterList>
    <ParameterList name="Enforcement">
      <Parameter name="Type" type="string" value="{strategy}"/>
      <ParameterList name="Penalty">
        <Parameter name="Normal Penalty Parameter" type="double" value="{eps_n:.17g}"/>   <!-- N/mm^2 on a line -->
        <Parameter name="Tangential Penalty Parameter" type="double" value="{eps_n / 10:.17g}"/>
      </ParameterList>
      <ParameterList name="Augmented Lagrange">
        <Parameter name="Normal Penalty Parameter" type="double" value="{eps_n:.17g}"/>
        <Parameter name="Tangential Penalty Parameter" type="double" value="{eps_n / 10:.17g}"/>
      </ParameterList>
    </ParameterList>
  </ParameterList>
  <ParameterList name="Load Stepping">
    <Parameter name="Number of Increments" type="int" value="{increments}"/>
  </ParameterList>
  <ParameterList name="Output">
    <ParameterList name="Tracked Points">
      <ParameterList name="rod1 middle">
        <Parameter name="Beam" type="string" value="rod1"/>
        <Parameter name="Node" type="string" value="middle"/>
      </ParameterList>
      <ParameterList name="rod1 below">   <!-- L / 8 below the middle -->
        <Parameter name="Beam" type="string" value="rod1"/>
        <Parameter name="Node" type="string" value="{elements // 2 - elements // 8}"/>
      </ParameterList>
      <ParameterList name="rod1 above">   <!-- L / 8 above the middle -->
        <Parameter name="Beam" type="string" value="rod1"/>
        <Parameter name="Node" type="string" value="{elements // 2 + elements // 8}"/>
      </ParameterList>
{rod2middle}    </ParameterList>
  </ParameterList>
</ParameterList>
"""
    return text


if __name__ == "__main__":
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--elements", type=int, default=16)
    a.add_argument("--increments", type=int, default=10)
    a.add_argument("--type", default="Penalty")
    a.add_argument("--eps", type=float, default=EPS_N)
    a.add_argument("--gauss", type=int, default=GAUSS)
    a.add_argument("--elements2", type=int, default=None, help="rod 2's elements (default: one fewer)")
    o = a.parse_args()
    print(deck(o.elements, o.increments, o.type, o.eps, o.gauss, o.elements2), end="")
