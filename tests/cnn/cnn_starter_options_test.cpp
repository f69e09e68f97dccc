// The learned starters' options (cnn_starter_options.hpp): the model path from the argument,
// kept whole, the hybrid policy from the name, and which model a starter loads.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "dc/cnn/cnn_starter_options.hpp"
#include "dc/core/error.hpp"
#include "dc/warmstart/warm_starter.hpp"
#include "warmstart/starter_error.hpp"

namespace dc {
namespace {

using test::spec;

TEST(CnnStarterOptions, DefaultsAndAcceptedForms) {
  const CnnStarterOptions d;
  EXPECT_TRUE(d.model.empty());
  EXPECT_FALSE(d.hybrid);
  const CnnStarterOptions plain = parse_cnn_options(spec("cnn"));
  EXPECT_TRUE(plain.model.empty());
  EXPECT_FALSE(plain.hybrid);
  const CnnStarterOptions hybrid = parse_cnn_options(spec("cnn-hybrid:models/impact.h5"));
  EXPECT_EQ(hybrid.model, std::filesystem::path("models/impact.h5"));
  EXPECT_TRUE(hybrid.hybrid);
  // A path is any text: its own ':' belong to it.
  EXPECT_EQ(parse_cnn_options(spec("cnn:runs/a:b.h5")).model, std::filesystem::path("runs/a:b.h5"));
  EXPECT_THROW((void)parse_cnn_options(spec("copy:models/impact.h5")), InvalidArgument);
}

TEST(CnnStarterOptions, TheArgumentThenTheRunsModelThenTheDefault) {
  const std::filesystem::path fallback = "models/default.h5";
  WarmStartEnv env;
  EXPECT_EQ(cnn_model_path(parse_cnn_options(spec("cnn")), env, fallback), fallback);
  env.model_path = "run.h5";
  EXPECT_EQ(cnn_model_path(parse_cnn_options(spec("cnn")), env, fallback), std::filesystem::path("run.h5"));
  EXPECT_EQ(cnn_model_path(parse_cnn_options(spec("cnn:mine.h5")), env, fallback), std::filesystem::path("mine.h5"));
}

}  // namespace
}  // namespace dc
