// Every method of the generated list (numerics/method_list.hpp) as GoogleTest's type list: the
// typed tests run on a new method as soon as its file exists, and fail to compile until the
// test's per-method expectations (Traits, Expected, Limit) name it too.
#pragma once

#include <gtest/gtest.h>

#include "numerics/method_list.hpp"

namespace cs::test {

template <class List>
struct GTestTypesOf;
template <class... Method>
struct GTestTypesOf<MethodList<Method...>> {
  using type = ::testing::Types<Method...>;
};

using AllMethods = GTestTypesOf<Methods>::type;

}  // namespace cs::test
