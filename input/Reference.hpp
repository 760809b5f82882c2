// The deck reference (beamcontact --print-valid-parameters) in three forms, each from the reference
// list (Deck.hpp: referenceParameters()):
//  - text: a parameter per entry, "NAME : TYPE, default: VALUE" (the value the reader fills in when the
//    parameter is left out), "NAME : TYPE, required, e.g. VALUE" or "NAME : TYPE, optional, e.g. VALUE"
//    (no fixed default: the text says what leaving it out does), then its meaning; sublists end in "/";
//  - xml: the deck format itself (Parameter name, type, value as the reader takes them back) with
//    use="default|required|optional" and the meaning as docString;
//  - yaml: the same as nested sequences (name, type, use, value as the deck's text, doc).
// Values are written as a deck takes them: bools true or false, numbers in their shortest exact form,
// arrays {a, b, c}.
#pragma once
#include <ostream>
#include <string>

#include <Teuchos_ParameterList.hpp>

namespace bc::input {

enum class ReferenceFormat { Text, Xml, Yaml };

void writeReference(const Teuchos::ParameterList& reference, ReferenceFormat format, std::ostream& out);

}  // namespace bc::input
