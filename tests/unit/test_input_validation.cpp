// Each kind of bad input gives an InputError whose text names the parameter's full path (and, for
// choices and misspelt keys, the valid names).
#include <gtest/gtest.h>

#include <regex>

#include "constraints/AugmentedLagrangeEnforcer.hpp"
#include "constraints/PenaltyEnforcer.hpp"
#include "support/TestSupport.hpp"

using namespace bc;

namespace {

// The rod's default section (1 x 1) and material (E = 100, nu = 0.3).
const std::string kSquare =
    R"XML(<Parameter name="Width" type="double" value="1"/><Parameter name="Height" type="double" value="1"/>)XML";
const std::string kMaterial =
    R"XML(<Parameter name="Young's Modulus" type="double" value="100"/><Parameter name="Poisson's Ratio" type="double" value="0.3"/>)XML";

std::string deck(const std::string& beamExtra = "", const std::string& section = kSquare,
                 const std::string& material = kMaterial,
                 const std::string& elements = R"XML(<Parameter name="Elements" type="int" value="4"/>)XML",
                 const std::string& end = "{10,0,0}", const std::string& rest = "") {
  return R"XML(<ParameterList name="BeamContact"><ParameterList name="Beams"><ParameterList name="rod">
    <Parameter name="Start" type="Array(double)" value="{0,0,0}"/>
    <Parameter name="End" type="Array(double)" value=")XML" +
         end + R"XML("/>)XML" + elements + beamExtra + R"XML(
    <ParameterList name="Section">)XML" +
         section + R"XML(</ParameterList>
    <ParameterList name="Material">)XML" +
         material + R"XML(</ParameterList>
  </ParameterList></ParameterList>
  <ParameterList name="Supports"><ParameterList name="clamp">
    <Parameter name="Beam" type="string" value="rod"/><Parameter name="Node" type="string" value="start"/>
  </ParameterList></ParameterList>)XML" +
         rest + "</ParameterList>";
}

void expectError(const std::string& xml, const std::string& pattern) {
  try {
    test::problemFromXml(xml);
    ADD_FAILURE() << "no error; expected one matching: " << pattern;
  } catch (const core::InputError& e) {
    EXPECT_TRUE(std::regex_search(std::string(e.what()), std::regex(pattern)))
        << "message: " << e.what() << "\nexpected to match: " << pattern;
  }
}

}  // namespace

TEST(InputValidation, ValidDeckBuilds) {
  const auto p = test::problemFromXml(deck());
  EXPECT_EQ(p.model.initial.numNodes(), 5);
  // Defaults filled in the effective list.
  EXPECT_EQ(p.effective.sublist("Linear Solver").get<std::string>("Type"), "Direct");
  EXPECT_EQ(p.effective.sublist("Load Stepping").get<int>("Number of Increments"), 10);
}

TEST(InputValidation, MistypedKeyIsNamedWithValidKeys) {
  expectError(deck(R"XML(<Parameter name="Elemnts" type="int" value="4"/>)XML"),
              R"XML(unknown parameter "BeamContact/Beams/rod/Elemnts"; valid parameters here are .*"Elements")XML");
}

TEST(InputValidation, WrongTypeIsNamed) {
  expectError(deck("", R"XML(<Parameter name="Width" type="string" value="wide"/>
      <Parameter name="Height" type="double" value="1"/>)XML"),
              R"XML(parameter "BeamContact/Beams/rod/Section/Width" has type string, expected double)XML");
}

TEST(InputValidation, NonPositiveYoungsModulus) {
  expectError(
      deck(
          "", kSquare,
          R"XML(<Parameter name="Young's Modulus" type="double" value="-5"/><Parameter name="Poisson's Ratio" type="double" value="0.3"/>)XML"),
      R"XML("BeamContact/Beams/rod/Material/Young's Modulus": must be > 0, got -5)XML");
}

TEST(InputValidation, MissingRequiredParameter) {
  expectError(deck("", kSquare, R"XML(<Parameter name="Poisson's Ratio" type="double" value="0.3"/>)XML"),
              R"XML(missing required parameter "BeamContact/Beams/rod/Material/Young's Modulus")XML");
  expectError(deck("", R"XML(<Parameter name="Width" type="double" value="1"/>)XML"),
              R"XML(missing required parameter "BeamContact/Beams/rod/Section/Height" for a Rectangle)XML");
}

TEST(InputValidation, ZeroElements) {
  expectError(deck("", kSquare, kMaterial, R"XML(<Parameter name="Elements" type="int" value="0"/>)XML"),
              R"XML("BeamContact/Beams/rod/Elements": must be from 1 to 10000000, got 0)XML");
}

TEST(InputValidation, ZeroLengthBeam) {
  expectError(deck("", kSquare, kMaterial, R"XML(<Parameter name="Elements" type="int" value="4"/>)XML", "{0,0,0}"),
              R"XML(beam "BeamContact/Beams/rod" has zero length)XML");
}

TEST(InputValidation, UnknownBeamName) {
  const std::string loads = R"XML(<ParameterList name="Loads"><ParameterList name="push">
      <Parameter name="Beam" type="string" value="bar"/><Parameter name="Node" type="string" value="end"/>
      <Parameter name="Force" type="Array(double)" value="{0,0,1}"/></ParameterList></ParameterList>)XML";
  expectError(
      deck("", kSquare, kMaterial, R"XML(<Parameter name="Elements" type="int" value="4"/>)XML", "{10,0,0}", loads),
      R"XML("BeamContact/Loads/push/Beam": unknown beam "bar"; beams are "rod")XML");
}

TEST(InputValidation, InvalidChoiceListsValidOnes) {
  const std::string solver =
      R"XML(<ParameterList name="Linear Solver"><Parameter name="Type" type="string" value="CG"/></ParameterList>)XML";
  expectError(
      deck("", kSquare, kMaterial, R"XML(<Parameter name="Elements" type="int" value="4"/>)XML", "{10,0,0}", solver),
      R"XML("BeamContact/Linear Solver/Type": "CG" is not a valid choice; valid choices are "Direct", "GMRES")XML");
}

TEST(InputValidation, NodeIndexOutOfRange) {
  const std::string loads = R"XML(<ParameterList name="Loads"><ParameterList name="push">
      <Parameter name="Beam" type="string" value="rod"/><Parameter name="Node" type="string" value="7"/>
      <Parameter name="Force" type="Array(double)" value="{0, 0, -1}"/></ParameterList></ParameterList>)XML";
  expectError(
      deck("", kSquare, kMaterial, R"XML(<Parameter name="Elements" type="int" value="4"/>)XML", "{10,0,0}", loads),
      R"XML("BeamContact/Loads/push/Node": "7" is not "start", "end", "middle" or an index 0..4)XML");
}

TEST(InputValidation, PenaltyParametersAreNumbersOrAutomatic) {
  // Penalty and Augmented Lagrange take "Automatic" in place of a penalty parameter; any other word,
  // a non-positive number or a target error outside (0, 1) is refused with the parameter's path.
  for (const core::ParameterSpec* spec :
       {&constraints::PenaltyEnforcer::spec(), &constraints::AugmentedLagrangeEnforcer::spec()}) {
    const std::string path = "BeamContact/Contact/Enforcement/S";
    auto apply = [&](const std::string& key, const Teuchos::ParameterEntry& value) {
      Teuchos::ParameterList l = spec->example();
      l.setEntry(key, value);
      spec->apply(l, path);
      return l;
    };
    auto refused = [&](const std::string& key, const Teuchos::ParameterEntry& value, const std::string& pattern) {
      try {
        apply(key, value);
        ADD_FAILURE() << key << ": no error; expected " << pattern;
      } catch (const core::InputError& e) {
        EXPECT_TRUE(std::regex_search(std::string(e.what()), std::regex(pattern))) << e.what();
      }
    };
    for (const char* key : {"Normal Penalty Parameter", "Tangential Penalty Parameter"}) {
      const auto l = apply(key, Teuchos::ParameterEntry(std::string("Automatic")));
      EXPECT_TRUE(core::ParameterSpec::isWord(l, key, "Automatic"));
      EXPECT_DOUBLE_EQ(apply(key, Teuchos::ParameterEntry(5.0)).get<double>(key), 5.0);
      refused(key, Teuchos::ParameterEntry(std::string("Automatc")),
              "parameter \"" + path + "/" + key + "\" is \"Automatc\"; give a number or \"Automatic\"");
      refused(key, Teuchos::ParameterEntry(-1.0), "\"" + path + "/" + key + "\": must be > 0");
    }
    for (const char* key : {"Normal Target Error", "Tangential Target Error"})
      for (double bad : {0.0, 1.0, 2.0})
        refused(key, Teuchos::ParameterEntry(bad), "\"" + path + "/" + key + "\": must be in \\(0, 1\\)");
  }
}
