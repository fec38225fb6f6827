#include "watch/kleene.h"

#include <gtest/gtest.h>

namespace dw::watch {
namespace {

// Truth tables of Kleene's strong three-valued logic, written out.
TEST(Kleene, And) {
  EXPECT_EQ(kleene_and(kTrue, kTrue), kTrue);
  EXPECT_EQ(kleene_and(kTrue, kFalse), kFalse);
  EXPECT_EQ(kleene_and(kTrue, kUnknown), kUnknown);
  EXPECT_EQ(kleene_and(kFalse, kUnknown), kFalse);
  EXPECT_EQ(kleene_and(kUnknown, kFalse), kFalse);
  EXPECT_EQ(kleene_and(kUnknown, kUnknown), kUnknown);
  EXPECT_EQ(kleene_and(kFalse, kFalse), kFalse);
}

TEST(Kleene, Or) {
  EXPECT_EQ(kleene_or(kFalse, kFalse), kFalse);
  EXPECT_EQ(kleene_or(kTrue, kFalse), kTrue);
  EXPECT_EQ(kleene_or(kTrue, kUnknown), kTrue);
  EXPECT_EQ(kleene_or(kUnknown, kTrue), kTrue);
  EXPECT_EQ(kleene_or(kFalse, kUnknown), kUnknown);
  EXPECT_EQ(kleene_or(kUnknown, kUnknown), kUnknown);
}

TEST(Kleene, Not) {
  EXPECT_EQ(kleene_not(kTrue), kFalse);
  EXPECT_EQ(kleene_not(kFalse), kTrue);
  EXPECT_EQ(kleene_not(kUnknown), kUnknown);
}

}  // namespace
}  // namespace dw::watch
