// Beam geometry of a deck: the nodes of a beam along a line, a polyline, an arc or a helix
// (internal to input/; Deck.cpp builds the beams from them).
#pragma once
#include <string>
#include <vector>

#include <Teuchos_Array.hpp>
#include <Teuchos_ParameterList.hpp>

#include "core/Parameters.hpp"
#include "elements/BeamSet.hpp"

namespace bc::input {

inline elements::Vec3d toVec(const Teuchos::Array<double>& a) { return {{a[0], a[1], a[2]}}; }

// The parameters of a beam's Arc and Helix sublists.
const core::ParameterSpec& arcSpec();
const core::ParameterSpec& helixSpec();

// The nodes of a beam along its geometry (exactly one of Start and End, Points, Arc, Helix), and its
// section orientation: given, or by default normal to the axis and global Z for straight beams and
// polylines, the plane's normal for an arc and the axis for a helix (both stay across the curve, so
// the section follows it: its local y axis is that vector projected on each element's normal plane).
std::vector<elements::Vec3d> beamPoints(Teuchos::ParameterList& b, const std::string& path, int ne,
                                        elements::Vec3d& sectionY);

}  // namespace bc::input
