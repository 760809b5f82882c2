// Helpers shared by the tests: decks from XML text, quiet runs into a scratch directory.
#pragma once
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>
#include <Teuchos_XMLParameterListHelpers.hpp>
#include <Tpetra_Core.hpp>

#include "core/Simulation.hpp"
#include "input/Deck.hpp"
#include "input/XmlDeck.hpp"

namespace bc::test {

// Full-precision text of a number (std::to_string keeps only 6 decimals).
inline std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

inline input::Problem problemFromXml(const std::string& xml, const std::string& name = "test") {
  return input::buildProblem(input::parseParameterXml(xml, name + " (test deck)"), name);
}

// A scratch folder under the system's temporary directory, named after the running test case too: CTest
// runs the cases of one program at the same time, each in its own process; every rank finds the same.
inline std::string scratchDirectory(const std::string& name) {
  std::string owner;
  if (const auto* t = ::testing::UnitTest::GetInstance()->current_test_info())
    owner = std::string(t->test_suite_name()) + "." + t->name() + "_";
  return (std::filesystem::temp_directory_path() / ("beamcontact_test_" + owner + name)).string();
}

inline core::RunResult runQuiet(input::Problem& p, Teuchos::RCP<const core::Comm> comm, const std::string& name) {
  core::RunOptions o;
  o.outputDirectory = scratchDirectory(name + "_np" + std::to_string(comm->getSize()));
  o.writeVtk = false;
  o.progress = false;
  o.overwrite = true;  // the tests' own scratch folder, perhaps left by a build before the manifest
  return core::simulate(p.model, p.solver, p.linearSolver, o, comm);
}

// A straight beam deck along X from the origin, clamped at its start, with a tip load.
inline std::string cantileverXml(double L, double width, double height, double E, double nu, int elements,
                                 const std::string& force, const std::string& moment, int increments,
                                 const std::string& extra = "") {
  const auto d = num;
  return R"XML(<ParameterList name="BeamContact">
  <ParameterList name="Beams"><ParameterList name="b">
    <Parameter name="Start" type="Array(double)" value="{0,0,0}"/>
    <Parameter name="End" type="Array(double)" value="{)XML" +
         d(L) + R"XML(,0,0}"/>
    <Parameter name="Elements" type="int" value=")XML" +
         std::to_string(elements) + R"XML("/>
    <ParameterList name="Section"><Parameter name="Width" type="double" value=")XML" +
         d(width) + R"XML("/>
      <Parameter name="Height" type="double" value=")XML" +
         d(height) + R"XML("/></ParameterList>
    <ParameterList name="Material"><Parameter name="Young's Modulus" type="double" value=")XML" +
         d(E) + R"XML("/>
      <Parameter name="Poisson's Ratio" type="double" value=")XML" +
         d(nu) + R"XML("/></ParameterList>
  </ParameterList></ParameterList>
  <ParameterList name="Supports"><ParameterList name="clamp">
    <Parameter name="Beam" type="string" value="b"/><Parameter name="Node" type="string" value="start"/>
  </ParameterList></ParameterList>
  <ParameterList name="Loads"><ParameterList name="tip">
    <Parameter name="Beam" type="string" value="b"/><Parameter name="Node" type="string" value="end"/>
    <Parameter name="Force" type="Array(double)" value="{)XML" +
         force + R"XML(}"/>
    <Parameter name="Moment" type="Array(double)" value="{)XML" +
         moment + R"XML(}"/>
  </ParameterList></ParameterList>
  <ParameterList name="Load Stepping"><Parameter name="Number of Increments" type="int" value=")XML" +
         std::to_string(increments) + R"XML("/></ParameterList>
  <ParameterList name="Output"><ParameterList name="Tracked Points"><ParameterList name="tip">
    <Parameter name="Beam" type="string" value="b"/><Parameter name="Node" type="string" value="end"/>
  </ParameterList></ParameterList></ParameterList>
  )XML" + extra +
         R"XML(
</ParameterList>)XML";
}

}  // namespace bc::test
