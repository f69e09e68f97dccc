// JsonWriter (bench/include/dc/bench/json_writer.hpp): escaping, the NaN/Inf policy, round-trip numbers,
// both layouts, and misuse errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <vector>

#include "dc/bench/json_writer.hpp"
#include "dc/core/error.hpp"

namespace dc {
namespace {

TEST(JsonWriter, EscapesQuotesBackslashesAndControlCharacters) {
  EXPECT_EQ(json_quote("plain"), "\"plain\"");
  EXPECT_EQ(json_quote("a\"b\\c"), "\"a\\\"b\\\\c\"");
  EXPECT_EQ(json_quote("l1\nl2\tx"), "\"l1\\nl2\\tx\"");
  EXPECT_EQ(json_quote(std::string("\x01\x1f\r", 3)), "\"\\u0001\\u001f\\u000d\"");
  EXPECT_EQ(json_quote(std::string("nul\0x", 5)), "\"nul\\u0000x\"");
  EXPECT_EQ(json_quote("θ ≤ 1e-6 N"), "\"θ ≤ 1e-6 N\"");  // UTF-8 bytes pass unchanged
}

TEST(JsonWriter, NonFiniteNumbersAreNull) {
  EXPECT_EQ(json_number(std::numeric_limits<double>::quiet_NaN()), "null");
  EXPECT_EQ(json_number(std::numeric_limits<double>::infinity()), "null");
  EXPECT_EQ(json_number(-std::numeric_limits<double>::infinity()), "null");
  JsonWriter j;
  j.begin_array().value(std::numeric_limits<double>::quiet_NaN()).value(std::optional<double>{}).value(1.5).end_array();
  EXPECT_EQ(j.str(), "[null, null, 1.5]\n");
}

TEST(JsonWriter, NumbersRoundTripExactly) {
  for (const double v : {0.1, 1.0 / 3.0, -2.5e-300, 6.02214076e23, 123456789.125, 5e-324,
                         std::numeric_limits<double>::max(), 0.0, -0.0}) {
    const std::string t = json_number(v);
    EXPECT_EQ(std::strtod(t.c_str(), nullptr), v) << t;
    EXPECT_EQ(std::signbit(std::strtod(t.c_str(), nullptr)), std::signbit(v)) << t;
  }
  JsonWriter j;
  j.begin_array().value(3).value(std::uint64_t{18446744073709551615ULL}).value(std::int64_t{-7}).value(true).value(false)
      .end_array();
  EXPECT_EQ(j.str(), "[3, 18446744073709551615, -7, true, false]\n");
}

TEST(JsonWriter, InlineAndLineLayouts) {
  JsonWriter j;
  j.begin_object(JsonWriter::Layout::Lines);
  j.key("a").begin_object(JsonWriter::Layout::Lines);
  j.key("x").begin_object().key("n").value(1).key("s").value("t").end_object();
  j.key("y").begin_object().end_object();
  j.end_object();
  const std::vector<double> z{1, 2.5};
  j.key("z").array(z);
  j.key("e").begin_array().end_array();
  j.end_object();
  EXPECT_EQ(j.str(),
            "{\n"
            "  \"a\": {\n"
            "    \"x\": {\"n\": 1, \"s\": \"t\"},\n"
            "    \"y\": {}\n"
            "  },\n"
            "  \"z\": [1, 2.5],\n"
            "  \"e\": []\n"
            "}\n");
}

TEST(JsonWriter, KeysAreEscapedToo) {
  JsonWriter j;
  j.begin_object().key("cnn:\"a\\b\"").value(std::string("v")).end_object();
  EXPECT_EQ(j.str(), "{\"cnn:\\\"a\\\\b\\\"\": \"v\"}\n");
}

TEST(JsonWriter, MisuseThrows) {
  {
    JsonWriter j;
    j.begin_object();
    EXPECT_THROW(j.value(1), InvalidArgument);  // value without key
  }
  {
    JsonWriter j;
    EXPECT_THROW(j.key("k"), InvalidArgument);  // key outside an object
  }
  {
    JsonWriter j;
    j.begin_array();
    EXPECT_THROW(j.end_object(), InvalidArgument);
    EXPECT_THROW((void)j.str(), InvalidArgument);  // incomplete
  }
  {
    JsonWriter j;
    j.begin_object().key("k");
    EXPECT_THROW(j.end_object(), InvalidArgument);  // key without value
  }
  {
    JsonWriter j;
    j.value(1);
    EXPECT_THROW(j.value(2), InvalidArgument);  // two top-level values
  }
}

}  // namespace
}  // namespace dc
