#pragma once
#include <gtest/gtest.h>

#include <string>

#include "engine/core/error.h"

// Expects `stmt` to throw cumulo::Error whose message contains `needle`.
#define EXPECT_ERROR_HAS(stmt, needle)                                                  \
  do {                                                                                  \
    try {                                                                               \
      stmt;                                                                             \
      ADD_FAILURE() << "no error thrown by " #stmt;                                     \
    } catch (const cumulo::Error& err) {                                                \
      EXPECT_NE(std::string(err.what()).find(needle), std::string::npos) << err.what(); \
    }                                                                                   \
  } while (0)
