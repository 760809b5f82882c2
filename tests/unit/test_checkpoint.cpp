// Checkpoint files (core/Checkpoint.hpp): the last line is the SHA-256 of every byte before it, and a
// file whose digest does not match, that lacks it, or that holds a non-finite number or a node whose
// rotation is not one is refused with a message naming the file. Expected digests are recomputed with
// core::sha256Hex (itself checked against FIPS 180-4's examples in test_sha256.cpp); rotations come
// from math::expSO3 of the node's own rotation vector.
#include <gtest/gtest.h>

#include <string>

#include "core/Checkpoint.hpp"
#include "core/Parameters.hpp"
#include "core/Sha256.hpp"
#include "core/State.hpp"

using bc::core::CheckpointIn;
using bc::core::CheckpointOut;
using bc::core::InputError;

namespace {

// The message of the InputError that `f` throws ("" when it throws none).
template <class F> std::string refusal(F f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bc::core::State rotatedState() {
  bc::core::State s;
  s.resize(2);
  s.position[1] = {{1.0, 2.0, 3.0}};
  s.rotationVector[1] = {{0.3, -0.2, 2.5}};
  s.rotation[1] = bc::math::expSO3(s.rotationVector[1]);
  return s;
}

}  // namespace

TEST(Checkpoint, LastLineIsTheSha256OfEverythingBefore) {
  CheckpointOut out;
  out.label("run").integer(40).real(0.8);
  out.state(rotatedState());
  const std::string text = out.text();
  ASSERT_EQ(text.back(), '\n');
  const std::size_t last = text.rfind('\n', text.size() - 2) + 1;
  EXPECT_EQ(text.substr(last), "sha256 " + bc::core::sha256Hex(text.substr(0, last)) + "\n");
  CheckpointIn in(text, "dir/checkpoint.txt");
  EXPECT_NO_THROW(in.verifyChecksum());
  in.label("run");
  EXPECT_EQ(in.integer(), 40);
  EXPECT_EQ(in.real(), 0.8);
  bc::core::State back = rotatedState();
  in.state(back);
  EXPECT_NO_THROW(in.finish());
}

TEST(Checkpoint, AnEditOrACutIsRefused) {
  CheckpointOut out;
  out.label("run").integer(40).real(0.8);
  const std::string text = out.text();
  std::string edited = text;
  edited[edited.find("40")] = '5';  // one digit of a number
  const std::string changed = refusal([&] { CheckpointIn(edited, "dir/checkpoint.txt").verifyChecksum(); });
  EXPECT_NE(changed.find("checkpoint dir/checkpoint.txt cannot be used: its SHA-256 checksum does not match"),
            std::string::npos)
      << changed;
  const std::string cut = text.substr(0, text.rfind('\n', text.size() - 2) + 1);  // without the last line
  const std::string missing = refusal([&] { CheckpointIn(cut, "dir/checkpoint.txt").verifyChecksum(); });
  EXPECT_NE(missing.find("its last line is not its checksum"), std::string::npos) << missing;
  // Text after the checksum line: the last line is then not the checksum.
  EXPECT_NE(refusal([&] { CheckpointIn(text + "end\n", "c").verifyChecksum(); }), "");
}

TEST(Checkpoint, NonFiniteNumbersAreRefused) {
  for (const char* word : {"nan", "inf", "-inf", "NAN"}) {
    CheckpointIn in(std::string("run\nT ") + word + "\n", "c");
    in.label("run");
    in.label("T");
    const std::string message = refusal([&] { in.real(); });
    EXPECT_NE(message.find(std::string("\"") + word + "\" is not a finite number on line 2"), std::string::npos)
        << message;
  }
}

TEST(Checkpoint, ARotationThatIsNotOneIsRefused) {
  bc::core::State s = rotatedState();
  s.rotation[1].m[0] += 1e-3;  // no longer orthonormal
  CheckpointOut out;
  out.state(s);
  bc::core::State back = rotatedState();
  CheckpointIn in(out.text(), "c");
  const std::string message = refusal([&] { in.state(back); });
  EXPECT_NE(message.find("node 1's rotation is not a rotation matrix"), std::string::npos) << message;

  bc::core::State t = rotatedState();
  t.rotationVector[1][2] += 1e-3;  // no longer the rotation's logarithm
  CheckpointOut out2;
  out2.state(t);
  CheckpointIn in2(out2.text(), "c");
  const std::string message2 = refusal([&] { in2.state(back); });
  EXPECT_NE(message2.find("node 1's rotation vector does not give its rotation"), std::string::npos) << message2;
}
