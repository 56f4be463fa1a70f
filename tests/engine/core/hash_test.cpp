// FNV-1a: the known vectors, and a string literal with a seed hashes the string (not `seed` bytes of it).
#include <gtest/gtest.h>

#include <string>

#include "engine/core/hash.h"

using namespace cumulo;

TEST(Hash, Fnv1aKnownVectors) {
  EXPECT_EQ(hash64(std::string_view("")), 0xcbf29ce484222325ull);
  EXPECT_EQ(hash64(std::string_view("a")), 0xaf63dc4c8601ec8cull);
  EXPECT_EQ(hash64(std::string_view("foobar")), 0x85944171f73967e8ull);
}

TEST(Hash, LiteralWithASeedHashesTheWholeLiteral) {
  const uint64_t seed = 123456789012345ull;  // far more than the literal's length
  EXPECT_EQ(hash64("lightning", seed), hash64(std::string_view("lightning"), seed));
  EXPECT_EQ(hash64("ab", 7), hash64(std::string("ab"), 7));
  EXPECT_NE(hash64("ab", 1), hash64("ab", 2));
}
