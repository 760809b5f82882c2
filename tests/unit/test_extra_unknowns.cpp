// Extra unknowns owned by several contributions (core::ExtraUnknowns): each owner's blocks keep their
// values while their keys persist, other owners' blocks are untouched, the numbering follows
// (owner, key) on every rank, and a checkpoint gives the layout and values back bit for bit.
#include <gtest/gtest.h>

#include "core/Checkpoint.hpp"
#include "core/State.hpp"

using bc::core::ExtraUnknowns;

TEST(ExtraUnknowns, OwnersKeepTheirValuesAcrossLayoutChanges) {
  ExtraUnknowns x;
  EXPECT_TRUE(x.request("contact", {{{0, 1, 2}, 3}, {{1, 0, 0}, 3}}));
  EXPECT_TRUE(x.request("joints", {{{7}, 2}}));
  ASSERT_EQ(x.size(), 8u);
  // Numbering by (owner, key): "contact" before "joints".
  EXPECT_EQ(x.find("contact", {0, 1, 2})->offset, 0);
  EXPECT_EQ(x.find("contact", {1, 0, 0})->offset, 3);
  EXPECT_EQ(x.find("joints", {7})->offset, 6);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = 10.0 + i;
  // The same request changes nothing.
  EXPECT_FALSE(x.request("contact", {{{0, 1, 2}, 3}, {{1, 0, 0}, 3}}));
  // A contact point leaves, another arrives: the staying one keeps its values, the new one starts at
  // zero, the joint's values move with it.
  EXPECT_TRUE(x.request("contact", {{{1, 0, 0}, 3}, {{2, 0, 0}, 3}}));
  const auto* kept = x.find("contact", {1, 0, 0});
  const auto* fresh = x.find("contact", {2, 0, 0});
  const auto* joint = x.find("joints", {7});
  ASSERT_TRUE(kept && fresh && joint);
  EXPECT_EQ(x.find("contact", {0, 1, 2}), nullptr);
  for (int j = 0; j < 3; ++j) {
    EXPECT_EQ(x[kept->offset + j], 13.0 + j);
    EXPECT_EQ(x[fresh->offset + j], 0.0);
  }
  EXPECT_EQ(x[joint->offset], 16.0);
  EXPECT_EQ(x[joint->offset + 1], 17.0);
  // A block whose size changes starts again at zero; a size of zero removes it.
  EXPECT_TRUE(x.request("joints", {{{7}, 1}}));
  EXPECT_EQ(x[x.find("joints", {7})->offset], 0.0);
  EXPECT_TRUE(x.request("joints", {{{7}, 0}}));
  EXPECT_EQ(x.find("joints", {7}), nullptr);
  EXPECT_EQ(x.size(), 6u);
  EXPECT_THROW(x.request("two words", {}), std::logic_error);
}

TEST(ExtraUnknowns, CheckpointRestoresLayoutAndValues) {
  bc::core::State s;
  s.resize(2);
  s.extra.request("contact", {{{0, 0, 1}, 3}});
  s.extra.request("joints", {{{4, 2}, 2}});
  for (std::size_t i = 0; i < s.extra.size(); ++i) s.extra[i] = 1.0 / (3.0 + i);
  bc::core::CheckpointOut out;
  out.state(s);
  bc::core::State back;
  back.resize(2);
  bc::core::CheckpointIn in(out.text(), "test");
  in.state(back);
  ASSERT_EQ(back.extra.size(), s.extra.size());
  for (std::size_t i = 0; i < s.extra.size(); ++i) EXPECT_EQ(back.extra[i], s.extra[i]);  // bit for bit
  EXPECT_EQ(back.extra.find("joints", {4, 2})->offset, s.extra.find("joints", {4, 2})->offset);
  EXPECT_FALSE(back.extra.request("contact", {{{0, 0, 1}, 3}}));
}
