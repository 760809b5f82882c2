// SHA-256 against the test vectors of FIPS 180-4's examples (NIST CSRC "Example Algorithms"):
// the empty message, "abc", the 448-bit two-block message, and one million 'a's fed in uneven pieces.
#include <gtest/gtest.h>

#include <string>

#include "core/Sha256.hpp"

using bc::core::Sha256;
using bc::core::sha256Hex;

TEST(Sha256, EmptyMessage) {
  EXPECT_EQ(sha256Hex(""), "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256, Abc) { EXPECT_EQ(sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"); }

TEST(Sha256, TwoBlocks) {
  EXPECT_EQ(sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq"),
            "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
}

TEST(Sha256, MillionAInPieces) {
  Sha256 sha;
  const std::string piece(997, 'a');  // a length prime to the block size
  std::size_t left = 1000000;
  while (left > 0) {
    const std::size_t n = std::min(left, piece.size());
    sha.update(piece.data(), n);
    left -= n;
  }
  EXPECT_EQ(sha.hex(), "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
}
