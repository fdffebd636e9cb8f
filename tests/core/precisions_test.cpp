// The one list of precisions (core/real_types.hpp) and everything derived from it: names, the
// runtime dispatch, sets of precisions as bits, and the truth's type.
#include "pldamp/core/real_types.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace pldamp {
namespace {

TEST(Precisions, NamesComeFromTheListNarrowestFirst) {
#if PLDAMP_WITH_QUAD
  EXPECT_EQ(precision_names(), "double|long|quad|50");
  static_assert(std::is_same_v<Precisions, RealList<double, long double, quad, bin50>>);
  static_assert(std::is_same_v<NarrowestWithDigits10<30>, quad>);
#else
  EXPECT_EQ(precision_names(), "double|long|50");
  static_assert(std::is_same_v<Precisions, RealList<double, long double, bin50>>);
  static_assert(std::is_same_v<NarrowestWithDigits10<30>, bin50>);
#endif
  static_assert(SupportedReal<long double> && !SupportedReal<float>);
  static_assert(std::is_same_v<NarrowestWithDigits10<15>, double>);
  std::vector<std::string> dispatched;
  for_each_precision([&]<class Real>() {
    with_precision(precision_name<Real>(), [&]<class Chosen>() {
      static_assert(std::is_same_v<Chosen, Chosen>);
      EXPECT_EQ((std::is_same_v<Real, Chosen>), true) << precision_name<Real>();
      dispatched.emplace_back(precision_name<Chosen>());
    });
  });
  std::string joined;
  for (const std::string& name : dispatched) {
    joined += (joined.empty() ? "" : "|") + name;
  }
  EXPECT_EQ(joined, precision_names());
}

TEST(Precisions, UnknownNamesAreRefusedWithTheList) {
  try {
    with_precision("float", []<class>() {});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "unknown precision, expected " + precision_names() + " (got float)");
  }
#if !PLDAMP_WITH_QUAD
  EXPECT_EQ(unknown_precision("quad"),
            "precision quad is not in this build "
            "(PLDAMP_WITH_QUAD=OFF), expected double|long|50 (got quad)");
#endif
}

TEST(Precisions, SetsAreBitsInListOrder) {
  EXPECT_EQ(precision_bit<double>(), 1u);
  EXPECT_EQ(precision_bit<long double>(), 2u);
  EXPECT_EQ(precision_bit("long"), 2u);
  EXPECT_EQ(precision_bit("float"), 0u);
  EXPECT_EQ(precision_names(precision_bit<double>() | precision_bit<bin50>()), "double|50");
  EXPECT_EQ(precision_names(every_precision), precision_names());
}

} // namespace
} // namespace pldamp
