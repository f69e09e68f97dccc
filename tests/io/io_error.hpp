#pragma once
// The message of the IoError that `f` throws; a test failure (and "") when it throws none.
#include <gtest/gtest.h>

#include <string>

#include "dc/core/error.hpp"

namespace dc::test {

template <class F>
std::string io_error(F&& f) {
  try {
    f();
  } catch (const IoError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected an IoError";
  return {};
}

}  // namespace dc::test
