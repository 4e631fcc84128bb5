#pragma once
// The message of the InputError an action throws, for tests that assert what it names.
#include <gtest/gtest.h>

#include <string>

#include "common/error.hpp"

namespace shapepress::testing {

// Runs `action` and returns the InputError's message; fails the test if nothing was thrown.
template <typename Action>
std::string input_error_of(Action action) {
  try {
    action();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError was thrown";
  return {};
}

}  // namespace shapepress::testing
